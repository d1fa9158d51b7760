// Fuzzes the EXR readers, on in-memory files: the RGBA `voxlux study` compares images with, the
// one channel a depth holdout reads, and an environment light's map, read, converted, oriented
// and cut into lights (render/environment_lights.h). Bad input must throw InputError; anything
// else is a defect.
#include <cstdint>

#include "core/error.h"
#include "in_memory_file.h"
#include "io/exr_reader.h"
#include "render/environment_lights.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static InMemoryFile file;
    try {
        voxlux::readExrRgba(file.write(data, size));
    } catch (const voxlux::InputError&) {
    }
    try {
        voxlux::readExrChannel(file.write(data, size), "Z");
    } catch (const voxlux::InputError&) {
    }
    try {
        voxlux::Scene scene;
        voxlux::Light sky;
        sky.type = voxlux::LightType::Environment;
        sky.environment = voxlux::EnvironmentSettings{};
        sky.environment->map = file.write(data, size);
        sky.environment->median_cut_lights = 8;
        scene.lights = {sky};
        voxlux::withEnvironmentLights(scene);
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
