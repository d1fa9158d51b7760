#include "viewer/scene_editor.h"

#include <filesystem>

#include "core/error.h"
#include "core/json_reader.h"
#include "io/exr_writer.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace {

// The index of the item of `items` (lights, volumes) named `name_or_index`, or of the index it
// spells; `kind` names them in the error.
template <class Item>
int indexByName(const std::vector<Item>& items, const nlohmann::json& name_or_index, const std::string& kind) {
    const int count = int(items.size());
    if (name_or_index.is_number_integer()) {
        const int i = name_or_index.get<int>();
        if (i < 0 || i >= count) throw InputError("no " + kind + " " + std::to_string(i) + " (the scene has " + std::to_string(count) + ")");
        return i;
    }
    if (!name_or_index.is_string()) throw InputError("a " + kind + " is named by its name or its index");
    for (int i = 0; i < count; ++i)
        if (items[size_t(i)].name == name_or_index.get<std::string>()) return i;
    throw InputError("no " + kind + " named \"" + name_or_index.get<std::string>() + "\"");
}

}  // namespace

SceneEditor::SceneEditor(Scene scene) : scene_(std::move(scene)), json_(sceneToJson(scene_)) {}

bool SceneEditor::edit(const std::string& what, const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json changed = json_;
    try {
        change(changed);
        // Paths in the JSON are already resolved: read it back with no folder to resolve against.
        Scene read = sceneFromJson(changed, what, "");
        const std::string kind = what.substr(0, what.find('='));
        if (kind != "camera") {
            if (!(merging_ && held_ && !undo_.empty() && undo_.back().kind == kind)) undo_.push_back({json_, kind});
            merging_ = held_;
            redo_.clear();
        }
        scene_ = std::move(read);
        json_ = sceneToJson(scene_);
        error_.clear();
        ++version_;
        return true;
    } catch (const std::exception& e) {
        error_ = e.what();
        return false;
    }
}

void SceneEditor::holdStep(bool held) {
    held_ = held;
    if (!held) merging_ = false;
}

bool SceneEditor::restore(std::vector<Step>& from, std::vector<Step>& to) {
    if (from.empty()) return false;
    nlohmann::json target = from.back().before;
    // The camera stays where navigation put it.
    if (json_.contains("camera")) target["camera"] = json_["camera"];
    else target.erase("camera");
    to.push_back({json_, from.back().kind});
    from.pop_back();
    scene_ = sceneFromJson(target, "undo", "");
    json_ = sceneToJson(scene_);
    error_.clear();
    solo_.reset();
    merging_ = false;
    ++version_;
    return true;
}

bool SceneEditor::undo() { return restore(undo_, redo_); }
bool SceneEditor::redo() { return restore(redo_, undo_); }

bool SceneEditor::set(const std::string& assignment) {
    return edit("set " + assignment, [&](nlohmann::json& j) { applySceneSet(j, assignment); });
}

void SceneEditor::adopt(const Scene& scene) {
    scene_ = scene;
    json_ = sceneToJson(scene_);
    // The edit that failed to render is undone already: its step goes, and nothing is left to redo.
    if (!undo_.empty() && undo_.back().before == json_) undo_.pop_back();
    redo_.clear();
    ++version_;
}

int SceneEditor::lightIndex(const nlohmann::json& name_or_index) const { return indexByName(scene_.lights, name_or_index, "light"); }

bool SceneEditor::addLight(const nlohmann::json& light) {
    solo_.reset();
    return edit("add light", [&](nlohmann::json& j) { j["lights"].push_back(light); });
}

bool SceneEditor::removeLight(int index) {
    solo_.reset();
    return edit("remove light", [&](nlohmann::json& j) { j.at("lights").erase(size_t(index)); });
}

bool SceneEditor::enableLight(int index, bool on) {
    return edit("enable light", [&](nlohmann::json& j) { j.at("lights").at(size_t(index))["enabled"] = on; });
}

bool SceneEditor::renameLight(int index, const std::string& name) {
    return edit("rename light", [&](nlohmann::json& j) { j.at("lights").at(size_t(index))["name"] = name; });
}

bool SceneEditor::changeLight(int index, const nlohmann::json& keys) {
    return edit("light " + std::to_string(index), [&](nlohmann::json& j) {
        nlohmann::json& light = j.at("lights").at(size_t(index));
        light.merge_patch(keys);
        // A type change drops the keys the new type does not take (a point light has no direction).
        const std::string type = light.value("type", "directional");
        if (type != "point" && type != "spot") light.erase("position");
        if (type != "directional" && type != "spot") light.erase("direction");
        if (type != "spot") light.erase("cone_angle"), light.erase("cone_softness");
        if (type == "point" || type == "spot")
            if (!light.contains("position")) light["position"] = {0, 0, 0};
        if (type == "directional" || type == "spot")
            if (!light.contains("direction")) light["direction"] = {0, -1, 0};
    });
}

bool SceneEditor::setLight(int index, const Light& light) {
    nlohmann::json keys = lightToJson(light);
    keys["enabled"] = light.enabled;
    return edit("light " + std::to_string(index), [&](nlohmann::json& j) { j.at("lights").at(size_t(index)) = keys; });
}

bool SceneEditor::enableVolume(int index, bool on) {
    const std::string pointer = "/volumes/" + std::to_string(index) + "/enabled";
    return edit(pointer, [&](nlohmann::json& j) { j[nlohmann::json::json_pointer(pointer)] = on; });
}

bool SceneEditor::setVolumeTransform(int index, const VolumeTransform& transform) {
    // Named as the panel's drags name it, so a held drag of either merges into one undo step.
    const std::string pointer = "/volumes/" + std::to_string(index) + "/transform";
    return edit(pointer, [&](nlohmann::json& j) { j[nlohmann::json::json_pointer(pointer)] = volumeTransformToJson(transform); });
}

int SceneEditor::volumeIndex(const nlohmann::json& name_or_index) const { return indexByName(scene_.volumes, name_or_index, "volume"); }

bool SceneEditor::soloLight(int index) {
    return solo("light " + std::to_string(index), [&](size_t i) { return int(i) == index; });
}

bool SceneEditor::soloGroup(const std::string& group) {
    // A light that names "default" is in the default group, as lightGroups has it.
    const auto named = [](const std::string& g) { return g.empty() ? std::string("default") : g; };
    return solo("group " + named(group), [&](size_t i) { return named(scene_.lights[i].group) == named(group); });
}

bool SceneEditor::solo(const std::string& what, const std::function<bool(size_t)>& lit) {
    const size_t count = scene_.lights.size();
    if (solo_ == what && before_solo_.size() == count) {
        const std::vector<bool> states = before_solo_;
        solo_.reset();
        return edit("unsolo " + what, [&](nlohmann::json& j) {
            for (size_t i = 0; i < count; ++i) j["lights"][i]["enabled"] = bool(states[i]);
        });
    }
    if (!solo_) {
        before_solo_.clear();
        for (const Light& l : scene_.lights) before_solo_.push_back(l.enabled);
    }
    std::vector<bool> on(count);
    for (size_t i = 0; i < count; ++i) on[i] = lit(i);
    solo_ = what;
    return edit("solo " + what, [&](nlohmann::json& j) {
        for (size_t i = 0; i < count; ++i) j["lights"][i]["enabled"] = bool(on[i]);
    });
}

bool SceneEditor::setCamera(const Camera& camera) {
    Scene with = scene_;
    with.camera = camera;
    const nlohmann::json keys = sceneToJson(with)["camera"];
    return edit("camera", [&](nlohmann::json& j) { j["camera"] = keys; });
}

void SceneEditor::save(const std::string& path) const {
    const std::string folder = std::filesystem::absolute(path).parent_path().string();
    writeFileAtomically(path, jsonText(sceneToJson(scenePathsRelativeTo(scene_, folder)), 2) + "\n");
}

}  // namespace voxlux
