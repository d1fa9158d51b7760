// The scene as the viewer edits it: its JSON (the form `voxlux scene` writes and the render graph
// hashes) and the Scene read back from it. Every edit, from a panel, a gizmo, a script or the
// camera, is a change of the JSON that must read back: a bad one leaves the scene as it was and
// keeps its one-line error, which the viewer shows. Every edit that took but the camera's is an
// undo step (the JSON before it: a few kB, kept for the session).
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace voxlux {

class SceneEditor {
public:
    explicit SceneEditor(Scene scene);

    const Scene& scene() const { return scene_; }
    const nlohmann::json& json() const { return json_; }
    // Increases with every edit that took, so a caller knows when to render again.
    uint64_t version() const { return version_; }
    // The error of the last edit that was refused, until the next edit that takes.
    const std::string& error() const { return error_; }

    // Applies `change` to the scene's JSON; `what` names the edit in its error. False if refused.
    bool edit(const std::string& what, const std::function<void(nlohmann::json&)>& change);
    // "KEY=VALUE" with a dotted key, as `voxlux render --set` takes it.
    bool set(const std::string& assignment);
    // Takes `scene` whole (the last good state after a failed render), keeping the error.
    void adopt(const Scene& scene);

    // Lights, by index in the scene's list. `light` is a light's JSON keys (docs/scene.md).
    bool addLight(const nlohmann::json& light);
    bool removeLight(int index);
    bool enableLight(int index, bool on);
    bool renameLight(int index, const std::string& name);
    bool changeLight(int index, const nlohmann::json& keys);   // merged over the light's keys
    bool setLight(int index, const Light& light);
    // Solo: only this light on, or only the lights of a light group (lights[i].group, "" or
    // "default" the default group; emission stays); the same solo again gives each light its state
    // back.
    bool soloLight(int index);
    bool soloGroup(const std::string& group);
    bool soloedLight(int index) const { return solo_ == "light " + std::to_string(index); }
    bool soloedGroup(const std::string& group) const { return solo_ == "group " + (group.empty() ? std::string("default") : group); }
    // The index of the light named `name`, or of the index `name` spells; throws InputError.
    int lightIndex(const nlohmann::json& name_or_index) const;

    // Volumes, by index in the scene's list: shown or not (a disabled volume is neither loaded
    // nor rendered), and placed by a transform (a gizmo drag).
    bool enableVolume(int index, bool on);
    bool setVolumeTransform(int index, const VolumeTransform& transform);
    // The index of the volume named `name`, or of the index `name` spells; throws InputError.
    int volumeIndex(const nlohmann::json& name_or_index) const;

    bool setCamera(const Camera& camera);

    // Undo and redo (Ctrl+Z, Ctrl+Shift+Z). The camera is not an undo step and stays where it is,
    // as navigation is in Houdini's and Blender's viewports. While a step is held (a mouse button
    // is down: a light dragged, a slider slid), edits of the same kind (the same key, the same
    // light) merge into one step. False when there is nothing to undo or redo.
    bool undo();
    bool redo();
    void holdStep(bool held);
    size_t undoSteps() const { return undo_.size(); }
    size_t redoSteps() const { return redo_.size(); }

    // Writes the scene to `path` (via a temporary file), its paths relative to the file's folder.
    void save(const std::string& path) const;

private:
    Scene scene_;
    nlohmann::json json_;
    uint64_t version_ = 0;
    std::string error_;
    std::optional<std::string> solo_;   // "light N" or "group NAME"
    std::vector<bool> before_solo_;
    bool solo(const std::string& what, const std::function<bool(size_t)>& lit);

    struct Step {
        nlohmann::json before;   // the scene's JSON before the step
        std::string kind;        // the edit's name up to its value ("set material.anisotropy", "light 0")
    };
    std::vector<Step> undo_, redo_;
    bool held_ = false;     // holdStep's
    bool merging_ = false;  // the newest step was opened while held: same-kind edits merge into it
    bool restore(std::vector<Step>& from, std::vector<Step>& to);
};

}  // namespace voxlux
