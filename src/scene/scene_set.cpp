// `--set KEY=VALUE` on a scene's JSON, before it is read: one dotted key at a time.
#include <algorithm>
#include <sstream>

#include "core/error.h"
#include "scene/scene_json.h"

namespace voxlux {

// The value is JSON when it parses as JSON (numbers, true, arrays, objects), else a string;
// objects on the way are created.
void applySceneSet(nlohmann::json& scene, const std::string& set) {
    const auto eq = set.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set '" + set + "': expected KEY=VALUE");
    const std::string text = set.substr(eq + 1);
    checkJsonDepth(text, "--set " + set.substr(0, eq));
    nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
    if (value.is_discarded()) value = text;
    nlohmann::json* node = &scene;
    std::stringstream keys(set.substr(0, eq));
    for (std::string key; std::getline(keys, key, '.');) {
        if (key.empty()) throw InputError("--set '" + set + "': empty key");
        if (!node->is_object()) *node = nlohmann::json::object();
        node = &(*node)[key];
    }
    *node = value;
}

std::string effectOnSet(const nlohmann::json& scene, const std::string& key) {
    std::string pointer = key;   // effects.indirect -> /effects/indirect
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    pointer.insert(pointer.begin(), '/');
    const nlohmann::json::json_pointer at(pointer);
    const bool has_settings = scene.contains(at) && scene[at].is_object();
    return key + "=" + (has_settings ? jsonText(scene[at]) : std::string("true"));
}

}  // namespace voxlux
