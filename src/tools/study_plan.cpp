#include "tools/study_plan.h"

#include <algorithm>
#include <map>
#include <optional>

#include "core/error.h"
#include "scene/quality_presets.h"
#include "render/renderer.h"
#include "render/write_stage.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace {

bool hasAmbientLight(const Scene& scene) {
    // (an environment light's floor is one: docs/environment.md)
    return std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
        return l.type == LightType::Ambient || (l.environment && l.environment->remainder == EnvironmentRemainder::Floor);
    });
}

// The sets that pick a method from scratch, whatever the scene had: every key the study varies is
// set, so a config means the same on every scene. `indirect_on` and `ao_on` keep the scene's own
// indirect and AO settings (transport colour, radius, ...) when it has them.
struct Methods {
    std::string indirect_on, ao_on;

    std::vector<std::string> march(const std::string& shadows, bool indirect, bool ao) const {
        return {"render.method=march", "effects.shadows=" + shadows,
                indirect ? indirect_on : "effects.indirect=false", ao ? ao_on : "effects.ambient_occlusion=false"};
    }
    // Propagation with Kniss's indirect light, whatever model the scene's own settings name.
    std::vector<std::string> kniss() const {
        std::vector<std::string> sets = march("propagation", true, false);
        sets.push_back("effects.indirect.model=\"kniss\"");
        return sets;
    }
};

// The family a scene's lighting belongs to, named as the sweeps name them.
std::string methodName(const Scene& s) {
    if (s.render.method == RenderMethod::Reference) return "reference";
    const std::string shadows = s.effects.shadows == ShadowMethod::None ? "unshadowed" : shadowMethodName(s.effects.shadows);
    const char* indirect = !s.effects.indirect ? "" : s.effects.indirect->model == IndirectModel::Kniss ? "+kniss" : "+indirect";
    return shadows + indirect +
           (s.effects.ambient_occlusion && hasAmbientLight(s) ? "+AO" : "");
}

// A sweep's points before they are merged into the plan.
struct Sweep {
    std::string method, knob;
    std::vector<StudyConfig> points;
    std::vector<std::string> labels;
};

// `knob` set to each of `values` on top of `base`. Without a knob each value is a whole
// "KEY=VALUE" (labelled by its last key) or "-" for `base` alone.
Sweep sweep(const std::string& method, const std::string& knob, const std::vector<std::string>& base,
            const std::vector<std::string>& values) {
    Sweep s{method, knob, {}, {}};
    for (const auto& v : values) {
        StudyConfig c{method, base, 0};
        if (!knob.empty()) c.sets.push_back(knob + "=" + v);
        else if (v != "-") c.sets.push_back(v);
        s.points.push_back(c);
        const std::string key = v.substr(0, v.find('='));
        s.labels.push_back(knob.empty() && v != "-" ? key.substr(key.rfind('.') + 1) : v);
    }
    return s;
}

}  // namespace

std::string StudyConfig::id() const {
    std::string s;
    for (const auto& set : sets) s += (s.empty() ? "" : " ") + set;
    return s;
}

namespace {

// The config's scene, or nothing when the scene refuses its settings; `skipped` gets the reason once.
std::optional<Scene> plannedScene(const nlohmann::json& base, const StudyConfig& config, std::vector<std::string>& skipped) {
    try {
        return studyScene(base, config);
    } catch (const InputError& e) {
        // The reason without the config's name ("study config '...': "), so that each is said once.
        std::string why = e.what();
        if (const size_t end = why.find("': "); why.rfind("study config '", 0) == 0 && end != std::string::npos) why.erase(0, end + 3);
        if (std::find(skipped.begin(), skipped.end(), why) == skipped.end()) skipped.push_back(why);
        return std::nullopt;
    }
}

}  // namespace

StudyPlan planStudy(const nlohmann::json& base, const std::vector<int>& spps, int seed) {
    const Scene scene = parseScene(base.dump(), "study scene", "");
    const Methods m{effectOnSet(base, "effects.indirect"), effectOnSet(base, "effects.ambient_occlusion")};

    // The knob values of each method's own accuracy study (docs/accuracy-sat.md,
    // docs/accuracy-propagation.md), plus the march step that every method shares.
    std::vector<Sweep> sweeps = {
        sweep("unshadowed", "", m.march("none", false, false), {"-"}),
        sweep("raymarch", "render.shadow_step", m.march("raymarch", false, false), {"4", "2", "1", "0.5"}),
        sweep("raymarch", "render.step", m.march("raymarch", false, false), {"1", "0.5", "0.25"}),
        sweep("sat_cone", "effects.light_resolution", m.march("sat_cone", false, false), {"64", "128", "192", "256"}),
        sweep("sat_cone", "effects.cone.samples", m.march("sat_cone", false, false), {"12", "20", "50"}),
        sweep("sat_cone", "effects.cone.angle", m.march("sat_cone", false, false), {"0.5", "2", "5"}),
        sweep("sat_cone", "render.step", m.march("sat_cone", false, false), {"1", "0.5"}),
        sweep("propagation", "effects.light_resolution", m.march("propagation", false, false), {"64", "128", "256"}),
        sweep("propagation+indirect", "effects.light_resolution", m.march("propagation", true, false), {"64", "128", "256"}),
        sweep("propagation+indirect", "effects.indirect.samples", m.march("propagation", true, false), {"3", "9", "17"}),
        sweep("propagation+indirect", "render.step", m.march("propagation", true, false), {"1", "0.5"}),
        sweep("propagation+indirect", "effects.indirect.strength", m.march("propagation", true, false), {"0.5", "1", "2", "4"}),
        // Kniss's artistic model, which the diffusion model replaced as the default: its transport colour.
        sweep("propagation+kniss", "effects.indirect.transport_color", m.kniss(),
              {"[0.4,0.4,0.4]", "[0.6,0.6,0.6]", "[0.8,0.8,0.8]", "[0.9,0.9,0.9]"}),
        sweep("propagation+indirect", "", m.march("propagation", true, false),
              {"effects.propagation.eye_pass=true", "effects.propagation.chroma_subsampling=true",
               "effects.propagation.blend_axes=true", "effects.propagation.filter=trilinear"}),
    };
    if (hasAmbientLight(scene)) {
        sweeps.push_back(sweep("raymarch+AO", "", m.march("raymarch", false, true), {"-"}));
        sweeps.push_back(sweep("sat_cone+AO", "effects.ambient_occlusion.shells", m.march("sat_cone", false, true), {"3", "7", "11"}));
        sweeps.push_back(sweep("sat_cone+AO", "effects.color_bleeding", m.march("sat_cone", false, true), {"0", "1"}));
        sweeps.push_back(sweep("propagation+indirect+AO", "", m.march("propagation", true, true), {"-"}));
    }
    // An environment light's median cut (docs/environment.md): its K lights and its remainder,
    // under each method that lights with them (the first environment light's).
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        if (!scene.lights[i].environment) continue;
        const std::string light = "lights." + std::to_string(i);
        const std::pair<std::string, std::vector<std::string>> methods[] = {{"raymarch", m.march("raymarch", false, false)},
                                                                            {"sat_cone", m.march("sat_cone", false, false)},
                                                                            {"propagation+indirect", m.march("propagation", true, false)}};
        for (const auto& [method, sets] : methods) {
            sweeps.push_back(sweep(method, light + ".median_cut_lights", sets, {"1", "4", "16", "64"}));
            sweeps.push_back(sweep(method, light + ".remainder", sets, {"floor", "none"}));
        }
        break;
    }
    Sweep reference{"reference", "render.reference.spp", {}, {}};
    for (int spp : spps) {
        reference.points.push_back({"reference",
                                    {"render.method=reference", "render.reference.spp=" + std::to_string(spp),
                                     "render.reference.seed=" + std::to_string(seed)},
                                    spp});
        reference.labels.push_back(std::to_string(spp));
    }
    sweeps.push_back(reference);
    // The presets last: where one is a config measured above, it is that row.
    StudyPlan plan;
    Sweep presets{kPresetSweep, "--quality", {}, {}};
    for (const std::string& name : qualityPresetNames()) {
        StudyConfig c{"", qualityPresetSets(base, name), 0};
        const std::optional<Scene> s = plannedScene(base, c, plan.skipped);
        if (!s) continue;
        c.method = methodName(*s);
        c.spp = s->render.method == RenderMethod::Reference ? s->render.reference.spp : 0;
        presets.points.push_back(c);
        presets.labels.push_back(name);
    }
    sweeps.push_back(presets);

    std::map<std::string, size_t> by_scene;   // scene hash -> config
    for (const Sweep& s : sweeps) {
        StudySweep out{s.method, s.knob, {}, {}};
        for (size_t i = 0; i < s.points.size(); ++i) {
            StudyConfig c = s.points[i];
            // The family is the scene's own: a scene with Kniss's indirect light keeps it throughout.
            const std::optional<Scene> scene = plannedScene(base, c, plan.skipped);
            if (!scene) continue;
            c.method = methodName(*scene);
            if (s.method != kPresetSweep) out.method = c.method;
            const std::string hash = sceneHash(*scene);
            auto [it, fresh] = by_scene.emplace(hash, plan.configs.size());
            if (fresh) plan.configs.push_back(c);
            out.configs.push_back(it->second);
            out.labels.push_back(s.labels[i]);
        }
        if (!out.configs.empty()) plan.sweeps.push_back(std::move(out));
    }
    return plan;
}

Scene studyScene(const nlohmann::json& base, const StudyConfig& config) {
    nlohmann::json j = base;
    for (const auto& set : config.sets) applySceneSet(j, set);
    return parseScene(j.dump(), "study config '" + config.id() + "'", "");
}

}  // namespace voxlux
