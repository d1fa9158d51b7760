// Flags to scene keys, read back through the scene reader together; a refused result is replayed
// flag by flag (a millisecond each at most), so the error names the flag that brought the value.
#include "tools/scene_overrides.h"

#include <cmath>
#include <functional>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "scene/quality_presets.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string part;
    while (std::getline(in, part, sep)) out.push_back(part);
    return out;
}

float parseFloat(const std::string& text, const std::string& context) {
    try {
        size_t used = 0;
        float v = std::stof(text, &used);
        if (used == text.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    throw InputError(context + ": '" + text + "' is not a number");
}

glm::vec3 parseVec3(const std::string& text, const std::string& context) {
    auto parts = split(text, ',');
    if (parts.size() != 3) throw InputError(context + ": expected three numbers x,y,z, got '" + text + "'");
    return {parseFloat(parts[0], context), parseFloat(parts[1], context), parseFloat(parts[2], context)};
}

// "directional:dir=1,-1,0:intensity=3" and so on, keys as in docs/cli.md, as the scene's light
// object. Only the syntax is checked here; the scene's own light reader validates the values.
nlohmann::json lightSpecJson(const std::string& spec, const std::string& context) {
    auto parts = split(spec, ':');
    nlohmann::json light = {{"type", parts.empty() ? std::string() : parts[0]}};
    const std::map<std::string, std::string> keys = {{"dir", "direction"}, {"pos", "position"}, {"color", "color"},
                                                     {"intensity", "intensity"}, {"angle", "cone_angle"},
                                                     {"softness", "cone_softness"}, {"group", "group"}};
    for (size_t i = 1; i < parts.size(); ++i) {
        auto eq = parts[i].find('=');
        if (eq == std::string::npos) throw InputError(context + ": expected key=value, got '" + parts[i] + "'");
        const std::string key = parts[i].substr(0, eq), value = parts[i].substr(eq + 1);
        const auto named = keys.find(key);
        if (named == keys.end()) throw InputError(context + ": unknown key '" + key + "' (dir, pos, color, intensity, angle, softness, group)");
        if (key == "group") {
            light["group"] = value;
        } else if (key == "dir" || key == "pos" || key == "color") {
            const glm::vec3 v = parseVec3(value, context);
            light[named->second] = {v.x, v.y, v.z};
        } else {
            light[named->second] = parseFloat(value, context);
        }
    }
    return light;
}

// Mantaflow (Blender) temperature: 0 ambient, 1.5 at ignition to 3 at the flames' maximum
// (Blender's defaults), x 1000 K as Blender's Principled Volume renders it at its default 1000 K.
// Brightness follows Planck's luminance, 1 at ignition; gas below 1000 K is dark.
nlohmann::json blackbodySource(const std::string& grid) {
    return {{"grid", grid}, {"kind", "blackbody"}, {"temperature_scale", 1000}, {"cutoff", 1000},
            {"normalization", "physical"}, {"reference_temperature", 1500}};
}

}  // namespace

Scene applyOverrides(const Scene& base, const SceneOverrides& o) {
    using Change = std::function<void(nlohmann::json&)>;
    std::vector<std::pair<std::string, Change>> changes;   // flag, what it does to the scene's JSON
    const auto apply = [&changes](const std::string& flag, Change change) { changes.emplace_back(flag, std::move(change)); };
    using Pointer = nlohmann::json::json_pointer;
    const auto setKey = [&](const std::string& flag, const char* key, const auto& value) {
        if (value) apply(flag, [key, v = *value](nlohmann::json& s) { s[Pointer(key)] = v; });
    };
    const auto finite = [](const char* flag, const std::optional<float>& value) {
        // JSON has no NaN or infinity (they would be written as null).
        if (value && !std::isfinite(*value))
            throw InputError(std::string(flag) + ": " + std::to_string(*value) + " is not a finite number");
        return value;
    };
    if (o.quality) apply("--quality " + *o.quality, [quality = *o.quality](nlohmann::json& s) { applyQualityPreset(s, quality); });
    setKey("--grid", "/volumes/0/density", o.grid);
    if (o.grid_index)
        apply("--grid-index", [name = o.grid.value_or(base.volume().density.name), index = *o.grid_index](nlohmann::json& s) {
            s["volumes"][0]["density"] = {{"name", name}, {"index", index}};
        });
    setKey("--color-grid", "/volumes/0/color", o.color_grid);
    setKey("--level-set", "/volumes/0/level_set", o.level_set);
    setKey("--up", "/volumes/0/up", o.up);
    if (o.emission_grid || o.blackbody_grid)
        apply(o.emission_grid ? "--emission-grid" : "--blackbody-grid", [o](nlohmann::json& s) {
            auto& sources = s["volumes"][0]["emission"] = nlohmann::json::array();
            if (o.emission_grid) sources.push_back({{"grid", *o.emission_grid}, {"kind", "constant"}, {"color", {1, 1, 1}}});
            if (o.blackbody_grid) sources.push_back(blackbodySource(*o.blackbody_grid));
        });
    if (o.deep) apply("--deep", [](nlohmann::json& s) { s["output"]["deep"] = true; });
    if (o.frames) apply("--frames " + *o.frames, [&o](nlohmann::json& s) { s["volumes"][0]["frames"] = *o.frames; });
    if (o.resolution) {
        const std::string flag = "--res " + *o.resolution;
        auto wh = split(*o.resolution, 'x');
        if (wh.size() != 2) throw InputError(flag + ": expected WIDTHxHEIGHT");
        const nlohmann::json resolution = {parseFloat(wh[0], flag), parseFloat(wh[1], flag)};
        apply(flag, [resolution](nlohmann::json& s) { s["render"]["resolution"] = resolution; });
    }
    setKey("--step", "/render/step", finite("--step", o.step));
    setKey("--filter", "/render/filter", o.filter);
    setKey("--shadow-step", "/render/shadow_step", finite("--shadow-step", o.shadow_step));
    setKey("--density-scale", "/volumes/0/material/density_scale", finite("--density-scale", o.density_scale));
    setKey("--backend", "/render/backend", o.backend);
    setKey("--method", "/render/method", o.method);
    setKey("--spp", "/render/reference/spp", o.spp);
    setKey("--shadows", "/effects/shadows", o.shadows);
    setKey("--pixel-type", "/output/pixel_type", o.pixel_type);
    setKey("--aovs", "/output/aovs", o.aovs);
    setKey("-o", "/output/path", o.output);
    setKey("--preview", "/output/preview", o.preview);
    if (!o.lights.empty()) {
        nlohmann::json lights = nlohmann::json::array();
        for (const auto& spec : o.lights) {
            const std::string flag = "--light '" + spec + "'";
            lights.push_back(lightSpecJson(spec, flag));
            readLight(JsonObject(lights.back(), flag, ""));
        }
        apply("--light", [lights](nlohmann::json& s) { s["lights"] = lights; });
    }
    for (const auto& set : o.sets) apply("--set '" + set + "'", [set](nlohmann::json& s) { applySceneSet(s, set); });

    // The flags are read together, so flags that only make sense together pass (--method march
    // with --backend gl on a reference scene); when the result is refused, they are replayed one
    // at a time to name the flag that made it so.
    nlohmann::json j = sceneToJson(base);
    for (const auto& [flag, change] : changes) change(j);
    try {
        return sceneFromJson(j, "command line", "");
    } catch (const InputError&) {
        nlohmann::json replay = sceneToJson(base);
        for (const auto& [flag, change] : changes) {
            change(replay);
            sceneFromJson(replay, flag, "");
        }
        throw;
    }
}

}  // namespace voxlux
