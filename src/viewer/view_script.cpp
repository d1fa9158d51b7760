#include "viewer/view_script.h"

#include <algorithm>
#include <map>

#include "core/error.h"
#include "core/json_reader.h"
#include "viewer/volume_gizmo.h"

namespace voxlux {
namespace {

enum class Shape { Text, Number, Bool, Light, Volume, Object, Pair, Wait, Region };

// Each kind, the shape of its value, and the other keys it takes.
const std::map<std::string, std::pair<Shape, std::vector<std::string>>>& kinds() {
    static const std::map<std::string, std::pair<Shape, std::vector<std::string>>> k = {
        {"set", {Shape::Text, {}}},          {"light", {Shape::Light, {"set"}}},       {"enable", {Shape::Light, {"on"}}},
        {"solo", {Shape::Light, {}}},        {"remove_light", {Shape::Light, {}}},    {"add_light", {Shape::Object, {}}},
        {"drag_light", {Shape::Light, {"by"}}}, {"orbit", {Shape::Pair, {}}},         {"pan", {Shape::Pair, {}}},
        {"dolly", {Shape::Number, {}}},      {"frame", {Shape::Bool, {}}},            {"frame_number", {Shape::Number, {}}},
        {"aov", {Shape::Text, {}}},          {"wait", {Shape::Wait, {}}},             {"wait_file", {Shape::Text, {"timeout"}}},
        {"screenshot", {Shape::Text, {}}},   {"window_screenshot", {Shape::Text, {}}}, {"layout", {Shape::Text, {}}},
        {"save", {Shape::Text, {}}},         {"render", {Shape::Bool, {}}},           {"stats", {Shape::Text, {}}},
        {"quit", {Shape::Bool, {}}},         {"undo", {Shape::Bool, {}}},             {"redo", {Shape::Bool, {}}},
        {"region", {Shape::Region, {}}},     {"drag_volume", {Shape::Volume, {"by", "mode"}}}, {"solo_group", {Shape::Text, {}}},
    };
    return k;
}

bool isPair(const nlohmann::json& v) { return v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number(); }
bool isRegion(const nlohmann::json& v) {
    return v == false || (v.is_array() && v.size() == 4 && std::all_of(v.begin(), v.end(), [](const nlohmann::json& x) { return x.is_number(); }));
}

}  // namespace

std::vector<ViewAction> loadViewScript(const std::string& path) {
    return parseViewScript(readFileText(path, "the view script"), path);
}

std::vector<ViewAction> parseViewScript(const std::string& text, const std::string& path) {
    const nlohmann::json root = parseJson(text, path);
    if (!root.is_object() || !root.contains("actions") || !root["actions"].is_array())
        throw InputError(path + ": a view script is an object with an \"actions\" array");
    JsonObject(root, path, "").rejectUnknown({"actions"});
    std::vector<ViewAction> actions;
    for (size_t k = 0; k < root["actions"].size(); ++k) {
        const nlohmann::json& a = root["actions"][k];
        const std::string where = path + ": /actions/" + std::to_string(k);
        if (!a.is_object() || a.empty()) throw InputError(where + ": an action is an object with one kind key");
        std::string kind;
        for (const auto& [key, value] : a.items())
            if (kinds().count(key) && kind.empty() && (key != "set" || !a.contains("light"))) kind = key;
        if (kind.empty()) throw InputError(where + ": unknown action \"" + a.begin().key() + "\"");
        const auto& [shape, extra] = kinds().at(kind);
        std::vector<std::string> known = extra;
        known.push_back(kind);
        JsonObject(a, path, "/actions/" + std::to_string(k)).rejectUnknown(known);
        const nlohmann::json& v = a[kind];
        const bool ok = shape == Shape::Text     ? v.is_string()
                        : shape == Shape::Number ? v.is_number()
                        : shape == Shape::Bool   ? v.is_boolean()
                        : shape == Shape::Light || shape == Shape::Volume ? v.is_string() || v.is_number_integer()
                        : shape == Shape::Object ? v.is_object()
                        : shape == Shape::Pair   ? isPair(v)
                        : shape == Shape::Region ? isRegion(v)
                                                 : v == "converged" || (v.is_number() && v.get<double>() >= 0);
        if (!ok) {
            const char* expected = shape == Shape::Text     ? "a string"
                                   : shape == Shape::Number ? "a number"
                                   : shape == Shape::Bool   ? "true or false"
                                   : shape == Shape::Light  ? "a light's name or index"
                                   : shape == Shape::Volume ? "a volume's name or index"
                                   : shape == Shape::Object ? "an object"
                                   : shape == Shape::Pair   ? "two numbers"
                                   : shape == Shape::Region ? "four numbers, or false"
                                                            : "\"converged\" or seconds";
            throw InputError(where + "/" + kind + ": must be " + expected);
        }
        if (kind == "light" && !(a.contains("set") && a["set"].is_object()))
            throw InputError(where + ": a light action needs \"set\": an object of the light's keys");
        if (kind == "enable" && !(a.contains("on") && a["on"].is_boolean()))
            throw InputError(where + ": an enable action needs \"on\": true or false");
        if (kind == "wait_file" && a.contains("timeout") && !(a["timeout"].is_number() && a["timeout"].get<double>() >= 0))
            throw InputError(where + "/timeout: must be seconds");
        if ((kind == "drag_light" || kind == "drag_volume") && !(a.contains("by") && isPair(a["by"])))
            throw InputError(where + ": a " + kind + " action needs \"by\": [dx, dy] in pixels");
        if (kind == "drag_volume" && a.contains("mode") &&
            std::find(kVolumeGizmoNames.begin(), kVolumeGizmoNames.end(), a["mode"]) == kVolumeGizmoNames.end())
            throw InputError(where + "/mode: must be move, rotate or scale");
        actions.push_back({kind, a, where});
    }
    return actions;
}

}  // namespace voxlux
