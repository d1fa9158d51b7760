#include "scene/quality_presets.h"

#include <map>
#include <vector>

#include "core/error.h"
#include "scene/scene_json.h"

namespace voxlux {

namespace {

// Each sets every key that picks the method, so a preset means the same whatever the scene had;
// lights, material, camera and output stay the scene's. Chosen from the Pareto fronts of
// docs/accuracy.md: AO is off because against multiple scattering it adds error on every scene
// measured.
const std::map<std::string, std::vector<std::string>>& presets() {
    static const std::map<std::string, std::vector<std::string>> p = {
        {"draft", {"render.method=march", "render.step=1", "effects.shadows=propagation", "effects.light_resolution=64",
                   "effects.indirect=true", "effects.propagation.chroma_subsampling=true",
                   "effects.propagation.filter=tricubic", "effects.ambient_occlusion=false"}},
        {"preview", {"render.method=march", "render.step=0.5", "effects.shadows=propagation",
                     "effects.light_resolution=128", "effects.indirect=true",
                     "effects.propagation.chroma_subsampling=false", "effects.propagation.filter=tricubic",
                     "effects.ambient_occlusion=false"}},
        {"final", {"render.method=reference", "render.reference.spp=256"}},
    };
    return p;
}

}  // namespace

const std::vector<std::string>& qualityPresetNames() {
    static const std::vector<std::string> names = {"draft", "preview", "final"};
    return names;
}

std::vector<std::string> qualityPresetSets(const nlohmann::json& scene, const std::string& name) {
    auto it = presets().find(name);
    if (it == presets().end()) throw InputError("--quality '" + name + "': unknown preset (draft, preview, final)");
    std::vector<std::string> sets;
    for (const std::string& set : it->second) {
        const auto eq = set.find('=');
        sets.push_back(set.substr(eq + 1) == "true" ? effectOnSet(scene, set.substr(0, eq)) : set);
    }
    return sets;
}

void applyQualityPreset(nlohmann::json& scene, const std::string& name) {
    for (const std::string& set : qualityPresetSets(scene, name)) applySceneSet(scene, set);
}

}  // namespace voxlux
