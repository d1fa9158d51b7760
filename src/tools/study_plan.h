// What `voxlux study` renders (docs/accuracy.md): every lighting method the scene can use, each
// quality knob swept with the others at their defaults, and the Monte Carlo reference at rising
// sample counts. Passes the scene does not call for are not studied (AO needs an ambient light).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace voxlux {

// One render of the study: the scene with `sets` ("KEY=VALUE", as --set) applied in order.
struct StudyConfig {
    std::string method;                  // the chart's family: "sat_cone", "propagation+indirect", "reference", ...
    std::vector<std::string> sets;
    int spp = 0;                         // reference samples per pixel; 0 for the approximations
    std::string id() const;              // the sets joined by spaces: equal settings, equal id
};

// The sweep that holds the --quality presets, labelled by preset name.
inline constexpr const char* kPresetSweep = "quality presets";

// One knob of one method swept through its values (a line on the chart).
struct StudySweep {
    std::string method, knob;            // "sat_cone", "effects.light_resolution"
    std::vector<size_t> configs;         // into StudyPlan::configs, in the order of the knob's values
    std::vector<std::string> labels;     // the knob's value at each point
};

struct StudyPlan {
    std::vector<StudySweep> sweeps;
    std::vector<StudyConfig> configs;    // every distinct render of the sweeps once, the reference last
    std::vector<std::string> skipped;    // why configs the scene refuses are left out, each reason once
};

// The plan for the scene whose JSON is `base`, with the reference at each of `spps` samples per
// pixel, seeded with `seed`. Configs that render the same scene (a knob at the value another
// sweep's default already has) are one config. Configs the scene refuses (several volumes refuse
// indirect light so far) are left out, and StudyPlan::skipped says why.
StudyPlan planStudy(const nlohmann::json& base, const std::vector<int>& spps, int seed);

// `base` (a scene's JSON) with `config`'s sets applied, parsed and validated.
Scene studyScene(const nlohmann::json& base, const StudyConfig& config);

}  // namespace voxlux
