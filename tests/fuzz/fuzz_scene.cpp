// Fuzzes the scene reader and `--set`: the input is a scene file's text, then, after a line "%%",
// one `--set KEY=VALUE` per line. Bad input must throw InputError; anything else is a defect.
#include <cstdint>
#include <sstream>
#include <string>

#include "core/error.h"
#include "scene/scene_json.h"
#include "tools/scene_overrides.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const size_t split = text.find("\n%%\n");
    voxlux::SceneOverrides overrides;
    if (split != std::string::npos) {
        std::istringstream sets(text.substr(split + 4));
        for (std::string line; std::getline(sets, line);) overrides.sets.push_back(line);
    }
    try {
        const voxlux::Scene scene = voxlux::parseScene(text.substr(0, split), "fuzz.json", "");
        voxlux::applyOverrides(scene, overrides);
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
