// Fuzzes the flags that carry their own syntax: the first line is `--frames`, the second `--res`,
// every further line a `--light` spec, applied to a scene with a #### volume path. Bad input must
// throw InputError; anything else is a defect.
#include <cstdint>
#include <sstream>
#include <string>

#include "core/error.h"
#include "tools/scene_overrides.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::istringstream lines(std::string(reinterpret_cast<const char*>(data), size));
    voxlux::SceneOverrides overrides;
    std::string line;
    if (std::getline(lines, line)) overrides.frames = line;
    if (std::getline(lines, line)) overrides.resolution = line;
    while (std::getline(lines, line)) overrides.lights.push_back(line);
    voxlux::Scene scene;
    scene.volume().path = "cache.####.vdb";
    scene.output.path = "out.####.exr";
    try {
        voxlux::applyOverrides(scene, overrides);
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
