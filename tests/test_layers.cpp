// The source folders are layers, and a file includes only headers of its own layer or lower ones
// (docs/architecture.md, Source layout), as Chromium's DEPS files check. The test reads every
// #include of src/ and shaders/ and fails on an upward one, naming both files and their layers.
// Each layer is also a static library, and a second test reads their symbol tables (nm) and fails
// when a library needs a voxlux symbol that only a library of a higher layer defines.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace voxlux::test {
namespace {

namespace fs = std::filesystem;

// Lowest first; each layer is the paths that match one of its patterns (from the start of the
// path), and a path belongs to the first layer that matches it. The kernel's data layout (its
// constants, parameter structs and page-table hash) sits below everything that bakes data for the
// kernel, and with them each lighting method's parameter blocks (its kernel/vx_<method>_types.h,
// which kernel_types.h reaches through the generated vx_lighting_types.h). The scene's
// description (scene.h) sits below optics, which reading a scene validates against; with it each
// lighting method's settings (its <method>_settings.h, which scene.h reaches through the generated
// method_settings.h), whose reading (<method>_settings.cpp) is the scene layer's. A lighting
// method's kernel/ folder (its kernel text and the output the march reads) is part of the kernel,
// which compiles every method's kernel text into one program.
struct Layer {
    std::string name;
    std::vector<std::string> patterns;
};
const std::vector<Layer> kLayers = {
    {"core", {"src/core/"}},
    {"kernel layout", {"shaders/vx_prelude\\.h$", "shaders/vx_types\\.h$", "src/kernel/kernel_types\\.h$",
                       "src/lighting/[^/]+/kernel/vx_[^/]+_types\\.h$"}},
    {"scene description", {"src/scene/scene\\.(h|cpp)$", "src/scene/filter\\.h$", "src/lighting/[^/]+/[^/]+_settings\\.h$"}},
    {"optics", {"src/optics/"}},
    {"scene", {"src/scene/", "src/lighting/[^/]+/[^/]+_settings\\.cpp$"}},
    {"graph", {"src/graph/"}},
    {"volume", {"src/volume/"}},
    {"kernel", {"src/kernel/", "shaders/", "src/lighting/[^/]+/kernel/"}},
    {"gl", {"src/gl/"}},
    {"io", {"src/io/"}},
    {"scan", {"src/scan/"}},
    {"lighting", {"src/lighting/"}},
    {"backend", {"src/backend/"}},
    {"reference", {"src/reference/"}},
    {"grade", {"src/grade/"}},
    {"render", {"src/render/"}},
    {"viewer", {"src/viewer/"}},
    {"tools", {"src/tools/"}},
};

int layerOf(const std::string& path) {
    for (size_t i = 0; i < kLayers.size(); ++i)
        for (const std::string& pattern : kLayers[i].patterns)
            if (std::regex_search(path, std::regex("^" + pattern))) return int(i);
    return -1;
}

// Every (file, header) include pair of the tree, as paths relative to the source root. A header
// is looked up beside the file, then from src/, then from shaders/, as the compiler does.
std::vector<std::pair<std::string, std::string>> includes(const fs::path& root) {
    static const std::regex include_line(R"re(^\s*#include "([^"]+)")re");
    std::vector<std::pair<std::string, std::string>> out;
    for (const char* top : {"src", "shaders"})
        for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
            const std::string ext = entry.path().extension().string();
            if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp" && ext != ".comp" && ext != ".glsl")) continue;
            std::ifstream in(entry.path());
            std::smatch m;
            for (std::string line; std::getline(in, line);) {
                if (!std::regex_search(line, m, include_line)) continue;
                for (const fs::path& dir : {entry.path().parent_path(), root / "src", root / "shaders"})
                    if (fs::exists(dir / m[1].str())) {
                        out.emplace_back(fs::relative(entry.path(), root).generic_string(),
                                         fs::relative(fs::canonical(dir / m[1].str()), fs::canonical(root)).generic_string());
                        break;
                    }
            }
        }
    return out;
}

TEST(Layers, EveryFolderIsALayer) {
    const fs::path root = sourceDir();
    std::set<std::string> unplaced;
    for (const auto& [file, header] : includes(root))
        for (const std::string& path : {file, header})
            if (layerOf(path) < 0) unplaced.insert(path);
    EXPECT_TRUE(unplaced.empty()) << "not in any layer of kLayers: " << *unplaced.begin();
}

TEST(Layers, PathsFallInTheirLayers) {
    const std::pair<const char*, const char*> cases[] = {
        {"src/core/error.h", "core"},
        {"shaders/vx_types.h", "kernel layout"},
        {"shaders/vx_march.h", "kernel"},
        {"src/scene/scene.h", "scene description"},
        {"src/scene/scene_read.cpp", "scene"},
        {"src/lighting/propagation/kernel/vx_propagation.h", "kernel"},
        {"src/lighting/propagation/cpu_propagation.cpp", "lighting"},
        {"src/lighting/new_method/kernel/vx_new.h", "kernel"},
        {"src/lighting/new_method/kernel/vx_new_types.h", "kernel layout"},
        {"src/lighting/new_method/new_method_settings.h", "scene description"},
        {"src/lighting/new_method/new_method_settings.cpp", "scene"},
        {"src/lighting/new_method/new_method_stages.h", "lighting"},
        {"src/tools/main.cpp", "tools"},
    };
    for (const auto& [path, layer] : cases) {
        ASSERT_GE(layerOf(path), 0) << path;
        EXPECT_EQ(kLayers[layerOf(path)].name, layer) << path;
    }
    EXPECT_EQ(layerOf("src/unknown/file.h"), -1);
}

TEST(Layers, NoFileIncludesALayerAboveItsOwn) {
    const fs::path root = sourceDir();
    std::ostringstream upward;
    for (const auto& [file, header] : includes(root))
        if (layerOf(header) > layerOf(file))
            upward << "\n  " << file << " (" << kLayers[layerOf(file)].name << ") -> " << header << " ("
                   << kLayers[layerOf(header)].name << ")";
    EXPECT_EQ(upward.str(), "") << "upward includes:";
}


// The voxlux symbols (functions, vtables, type infos) an archive defines, or needs from elsewhere.
std::set<std::string> voxluxSymbols(const std::string& archive, bool defined) {
    const std::string command = "nm -C " + std::string(defined ? "--defined-only" : "--undefined-only") + " '" + archive + "'";
    std::set<std::string> out;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return out;
    static const std::regex symbol_line(R"re(^[0-9a-f]* +[A-Za-z] ((vtable for |typeinfo for )?voxlux::.*)$)re");
    char buffer[4096];
    std::smatch m;
    while (std::fgets(buffer, sizeof buffer, pipe)) {
        std::string line(buffer);
        if (!line.empty() && line.back() == '\n') line.pop_back();
        if (std::regex_match(line, m, symbol_line)) out.insert(m[1].str());
    }
    EXPECT_EQ(pclose(pipe), 0) << command;
    return out;
}

TEST(Layers, NoLibraryNeedsALayerAboveItsOwn) {
    // The layers' archives, lowest first (VOXLUX_LAYERS in CMakeLists.txt).
    std::vector<std::string> archives;
    std::stringstream list(layerLibraries());
    for (std::string archive; std::getline(list, archive, ',');) archives.push_back(archive);
    ASSERT_GE(archives.size(), 13u);
    std::set<std::string> below;  // defined by this layer's library or a lower one
    std::ostringstream upward;
    for (const std::string& archive : archives) {
        const std::set<std::string> defined = voxluxSymbols(archive, true);
        ASSERT_FALSE(defined.empty()) << archive;
        below.insert(defined.begin(), defined.end());
        for (const std::string& needed : voxluxSymbols(archive, false))
            if (!below.count(needed)) upward << "\n  " << fs::path(archive).filename().string() << " needs " << needed;
    }
    EXPECT_EQ(upward.str(), "") << "symbols only a higher layer defines:";
}

}  // namespace
}  // namespace voxlux::test
