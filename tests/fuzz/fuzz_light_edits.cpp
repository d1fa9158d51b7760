// Fuzzes the light-edit reader and applies each edit to a rig of four lights (no render): the
// input is a light-edit file's text. Bad input must throw InputError; anything else is a defect.
#include <cstdint>
#include <string>

#include "core/error.h"
#include "render/light_edits.h"
#include "render/light_rig.h"
#include "render/renderer.h"
#include "scene/camera.h"

namespace {

voxlux::Scene rigScene() {
    voxlux::Scene s;
    for (int k = 0; k < 4; ++k) {
        voxlux::Light l = voxlux::defaultKeyLight();
        l.name = "light" + std::to_string(k);
        s.lights.push_back(l);
    }
    return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const voxlux::Scene scene = rigScene();
    static voxlux::Renderer renderer(scene);   // the rig only holds it: edits are not applied to it
    try {
        voxlux::LightRig rig(renderer, scene);
        for (const auto& edit : voxlux::parseLightEdits(std::string(reinterpret_cast<const char*>(data), size), "edits.json"))
            voxlux::applyLightEdit(rig, edit);
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
