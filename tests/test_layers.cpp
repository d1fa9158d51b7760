// The source folders are layers, and a file includes only headers of its own layer or lower ones
// (docs/architecture.md, Source layout), as Chromium's DEPS files check. The test reads every
// #include of src/ and shaders/ and fails on an upward one that is not in kKnownUpward, and on an
// entry of kKnownUpward that no longer occurs, so the list can only shrink.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace voxlux::test {
namespace {

namespace fs = std::filesystem;

// Lowest first. shaders/ is the kernel text every layer from the kernel up may use.
const std::vector<std::vector<std::string>> kLayers = {
    {"src/core/"},
    {"src/scene/"},
    {"src/optics/"},
    {"src/volume/"},
    {"src/kernel/", "shaders/"},
    {"src/io/"},
    {"src/lighting/"},
    {"src/backend/"},
    {"src/reference/"},
    {"src/grade/"},
    {"src/render/"},
    {"src/tools/"},
};

// Upward includes still to remove (issue 22): the kernel includes the lighting methods' kernel
// text and outputs; the stages of lower layers include the render graph; the methods' GL passes
// include the GL backend's buffers; bakers read the kernel's constants.
const std::set<std::string> kKnownUpward = {
    "shaders/vx_march.h -> src/lighting/extinction_sat/vx_cache.h",
    "shaders/vx_march.h -> src/lighting/propagation/vx_illumination.h",
    "src/backend/gl/gl_color_transform.h -> src/grade/color_transformer.h",
    "src/grade/color_stages.h -> src/render/render_graph.h",
    "src/grade/grade_stage.h -> src/render/march_stage.h",
    "src/grade/grade_stage.h -> src/render/render_graph.h",
    "src/kernel/cpu_kernel.h -> src/lighting/extinction_sat/vx_sat.h",
    "src/kernel/cpu_kernel.h -> src/lighting/propagation/vx_propagation.h",
    "src/kernel/kernel_inputs.h -> src/lighting/extinction_sat/light_cache.h",
    "src/kernel/kernel_inputs.h -> src/lighting/propagation/illumination_volume.h",
    "src/lighting/extinction_sat/extinction_sat_stages.h -> src/render/render_graph.h",
    "src/lighting/extinction_sat/gl_sat_passes.cpp -> src/backend/gl/gl_buffer.h",
    "src/lighting/extinction_sat/gl_sat_passes.cpp -> src/backend/gl/gl_context.h",
    "src/lighting/propagation/gl_propagation_passes.cpp -> src/backend/gl/gl_buffer.h",
    "src/lighting/propagation/gl_propagation_passes.cpp -> src/backend/gl/gl_context.h",
    "src/lighting/propagation/propagation_stages.h -> src/render/render_graph.h",
    "src/optics/emission.cpp -> shaders/vx_prelude.h",
    "src/optics/noise_table.cpp -> src/kernel/kernel_types.h",
    "src/optics/transfer_function.cpp -> shaders/vx_prelude.h",
    "src/scene/scene_read.cpp -> src/kernel/kernel_types.h",
    "src/scene/scene_read.cpp -> src/optics/emission.h",
    "src/volume/brick_atlas.cpp -> shaders/vx_prelude.h",
    "src/volume/page_table.cpp -> src/kernel/cpu_kernel.h",
    "src/volume/volume_stages.h -> src/render/render_graph.h",
};

int layerOf(const std::string& path) {
    for (size_t i = 0; i < kLayers.size(); ++i)
        for (const std::string& prefix : kLayers[i])
            if (path.rfind(prefix, 0) == 0) return int(i);
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
    const fs::path root = VOXLUX_SOURCE_DIR;
    std::set<std::string> unplaced;
    for (const auto& [file, header] : includes(root))
        for (const std::string& path : {file, header})
            if (layerOf(path) < 0) unplaced.insert(path);
    EXPECT_TRUE(unplaced.empty()) << "not in any layer of kLayers: " << *unplaced.begin();
}

TEST(Layers, NoFileIncludesALayerAboveItsOwn) {
    const fs::path root = VOXLUX_SOURCE_DIR;
    std::set<std::string> upward;
    for (const auto& [file, header] : includes(root))
        if (layerOf(header) > layerOf(file)) upward.insert(file + " -> " + header);
    std::ostringstream added, removed;
    for (const std::string& u : upward)
        if (!kKnownUpward.count(u)) added << "\n  " << u;
    for (const std::string& k : kKnownUpward)
        if (!upward.count(k)) removed << "\n  " << k;
    EXPECT_EQ(added.str(), "") << "upward includes:";
    EXPECT_EQ(removed.str(), "") << "no longer upward, take them out of kKnownUpward:";
}

}  // namespace
}  // namespace voxlux::test
