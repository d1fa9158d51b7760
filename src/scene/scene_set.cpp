// `--set KEY=VALUE` on a scene's JSON, before it is read: one dotted key at a time.
#include <algorithm>
#include <sstream>

#include "core/error.h"
#include "scene/scene_json.h"

namespace voxlux {

namespace {

// An element of an array by its index or by its "name" (volumes.smoke, lights.key).
nlohmann::json& element(nlohmann::json& array, const std::string& key, const std::string& set) {
    for (size_t i = 0; i < array.size(); ++i)
        if (key == std::to_string(i) || (array[i].is_object() && array[i].value("name", "") == key)) return array[i];
    throw InputError("--set '" + set + "': no element '" + key + "' (an index below " + std::to_string(array.size()) + " or a name)");
}

}  // namespace

// The value is JSON when it parses as JSON (numbers, true, arrays, objects), else a string;
// objects on the way are created, arrays are entered by index or name. A scene's `volume`,
// `material` and `emission` are its one volume's (volumes.0), as a scene file of one volume
// spells them.
void applySceneSet(nlohmann::json& scene, const std::string& set) {
    const auto eq = set.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set '" + set + "': expected KEY=VALUE");
    const std::string text = set.substr(eq + 1);
    checkJsonDepth(text, "--set " + set.substr(0, eq));
    nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
    if (value.is_discarded()) value = text;
    std::vector<std::string> keys;
    std::stringstream dotted(set.substr(0, eq));
    for (std::string key; std::getline(dotted, key, '.');) {
        if (key.empty()) throw InputError("--set '" + set + "': empty key");
        keys.push_back(key);
    }
    const bool one_volume_key = keys[0] == "volume" || keys[0] == "material" || keys[0] == "emission";
    if (one_volume_key && scene.contains("volumes") && !scene.contains("volume")) {
        if (scene["volumes"].size() != 1)
            throw InputError("--set '" + set + "': the scene has " + std::to_string(scene["volumes"].size()) +
                             " volumes; name one, as volumes.<name>." + (keys[0] == "volume" ? "" : keys[0] + "."));
        if (keys[0] == "volume") keys.erase(keys.begin());
        keys.insert(keys.begin(), {"volumes", "0"});
    }
    nlohmann::json* node = &scene;
    for (const std::string& key : keys) {
        if (node->is_array()) {
            node = &element(*node, key, set);
            continue;
        }
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
