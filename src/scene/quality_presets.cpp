#include "scene/quality_presets.h"

#include <map>
#include <vector>

#include "core/error.h"
#include "scene/scene_json.h"

namespace voxlux {

namespace {

// Each sets every key that picks the method, so a preset means the same whatever the scene had;
// lights (but for an environment light's median-cut count, below), material, camera and output
// stay the scene's. Chosen from the Pareto fronts of
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

// The median-cut lights each environment light gets under a fast preset: on the three scenes of
// docs/accuracy.md ("Environment light: the median cut's K"), 4 lights give propagation with
// indirect light the mean error of 16 (worse on one scene, better on two) in about half the time.
const std::map<std::string, int>& environmentLights() {
    static const std::map<std::string, int> k = {{"draft", 4}, {"preview", 4}};
    return k;
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
    if (auto k = environmentLights().find(name); k != environmentLights().end() && scene.contains("lights") && scene["lights"].is_array())
        for (size_t i = 0; i < scene["lights"].size(); ++i)
            if (scene["lights"][i].is_object() && scene["lights"][i].value("type", "") == "environment")
                sets.push_back("lights." + std::to_string(i) + ".median_cut_lights=" + std::to_string(k->second));
    return sets;
}

void applyQualityPreset(nlohmann::json& scene, const std::string& name) {
    for (const std::string& set : qualityPresetSets(scene, name)) applySceneSet(scene, set);
}

}  // namespace voxlux
