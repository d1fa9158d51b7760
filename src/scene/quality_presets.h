// `--quality draft|preview|final`: settings picked from the Pareto front that `voxlux study`
// measured on the shared smoke, fire and cloud (docs/accuracy.md, which prints each preset's
// error and time).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace voxlux {

// draft, preview, final.
const std::vector<std::string>& qualityPresetNames();

// The preset's settings for the scene whose JSON is `scene`, as "KEY=VALUE" (--set) in order. An
// effect the preset turns on keeps the scene's own settings of it (effectOnSet); draft and
// preview set each environment light's median_cut_lights. Throws
// InputError "--quality 'X': unknown preset (draft, preview, final)".
std::vector<std::string> qualityPresetSets(const nlohmann::json& scene, const std::string& name);

// Applies qualityPresetSets to `scene`.
void applyQualityPreset(nlohmann::json& scene, const std::string& name);

}  // namespace voxlux
