#include "render/light_edits.h"

#include "core/error.h"
#include "core/json_reader.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace {

// The kinds of edit: each edit object has exactly one of these keys.
const std::vector<std::string> kKinds = {"add", "remove", "toggle", "light"};

std::string kindOf(const LightEdit& e) {
    const JsonObject o(e.value, e.file, e.pointer);
    std::string kind;
    for (const auto& k : kKinds)
        if (o.has(k)) {
            if (!kind.empty())
                throw InputError(e.file + ": " + e.pointer + ": an edit has exactly one of add, remove, toggle, light");
            kind = k;
        }
    if (kind.empty()) throw InputError(e.file + ": " + e.pointer + ": an edit needs one of add, remove, toggle, light");
    if (kind == "light") o.rejectUnknown({"light", "set"});
    else if (kind == "toggle") o.rejectUnknown({"toggle", "on"});
    else o.rejectUnknown({kind});
    return kind;
}

// The light an edit names: by its "name", or by id (the index in the scene's lights; added
// lights take the next ids).
int target(const LightRig& rig, const LightEdit& e, const std::string& key) {
    const JsonObject o(e.value, e.file, e.pointer);
    const nlohmann::json& v = o.raw(key);
    if (v.is_number_integer()) {
        const int id = v.get<int>();
        for (int known : rig.ids())
            if (known == id) return id;
        o.fail(key, "no light with id " + std::to_string(id));
    }
    if (!v.is_string()) o.fail(key, "must be a light's name or id");
    if (auto id = rig.find(v.get<std::string>())) return *id;
    std::string names;
    for (int id : rig.ids())
        if (!rig.light(id).name.empty()) names += (names.empty() ? "" : ", ") + rig.light(id).name;
    o.fail(key, "no light named \"" + v.get<std::string>() + "\" (named lights: " + (names.empty() ? "none" : names) + ")");
}

Light readEditedLight(const nlohmann::json& value, const LightEdit& e, const std::string& key) {
    return readLight(JsonObject(value, e.file, e.pointer + "/" + key));
}

}  // namespace

std::vector<LightEdit> loadLightEdits(const std::string& path) {
    return parseLightEdits(readFileText(path, "the light-edit file"), path);
}

std::vector<LightEdit> parseLightEdits(const std::string& text, const std::string& path) {
    const nlohmann::json root = parseJson(text, path);
    const JsonObject o(root, path, "");
    if (!root.is_object()) throw InputError(path + ": a light-edit file is an object with an \"edits\" array");
    o.rejectUnknown({"edits"});
    const nlohmann::json& edits = o.raw("edits");
    if (!edits.is_array()) o.fail("edits", "must be an array of edits");
    std::vector<LightEdit> out;
    for (size_t k = 0; k < edits.size(); ++k) {
        LightEdit e{edits[k], path, "/edits/" + std::to_string(k)};
        if (!e.value.is_object()) throw InputError(path + ": " + e.pointer + ": an edit must be an object");
        kindOf(e);
        out.push_back(std::move(e));
    }
    return out;
}

std::string applyLightEdit(LightRig& rig, const LightEdit& e) {
    const std::string kind = kindOf(e);
    const JsonObject o(e.value, e.file, e.pointer);
    auto label = [&](int id) { return rig.light(id).name.empty() ? "light " + std::to_string(id) : rig.light(id).name; };
    if (kind == "add") {
        const int id = rig.add(readEditedLight(o.raw("add"), e, "add"));
        return "add " + label(id);
    }
    if (kind == "remove") {
        const int id = target(rig, e, "remove");
        const std::string name = label(id);
        rig.remove(id);
        return "remove " + name;
    }
    if (kind == "toggle") {
        const int id = target(rig, e, "toggle");
        const bool on = o.boolean("on", !rig.light(id).enabled);
        rig.toggle(id, on);
        return "toggle " + label(id) + (on ? " on" : " off");
    }
    const int id = target(rig, e, "light");
    if (!o.has("set") || !o.raw("set").is_object()) o.fail("set", "must be an object of the light keys to change");
    // The light's keys with the edit's on top; a type change drops the keys the new type lacks.
    nlohmann::json merged = lightToJson(rig.light(id));
    if (!rig.light(id).enabled) merged["enabled"] = false;
    merged.merge_patch(o.raw("set"));
    if (merged.contains("type") && merged["type"] == "ambient")  // any JSON type: the light reader names a bad one
        for (const char* key : {"position", "direction", "cone_angle", "cone_softness"})
            if (!o.raw("set").contains(key)) merged.erase(key);
    rig.update(id, readEditedLight(merged, e, "set"));
    return "update " + label(id);
}

}  // namespace voxlux
