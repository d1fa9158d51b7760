// Interactive editing of a scene's lights (Sunden 2015's sequential editing), for the viewer and
// the sequence renderer: lights get stable ids, edits mark them dirty, and apply() hands the
// edited scene to a Renderer, whose illumination stage then takes out and puts back only the
// lights that changed (or recomputes all of them when that is estimated cheaper).
#pragma once
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/scene.h"

namespace voxlux {

// What one apply() did.
struct LightRigUpdate {
    std::vector<int> dirty;               // ids edited since the previous apply
    std::optional<LightUpdate> lighting;  // the illumination stage's update (none if it did not run)
    double seconds = 0.0;                 // wall time of the stages brought up to date
    std::vector<std::pair<std::string, double>> stage_seconds;
};

class LightRig {
public:
    // The scene's lights get ids 0, 1, ... in order. The renderer is driven by apply().
    LightRig(Renderer& renderer, Scene scene);

    int add(const Light& light);                 // returns the new light's id
    void remove(int id);
    void update(int id, const Light& light);
    void toggle(int id, bool on);
    const Light& light(int id) const;
    std::optional<int> find(const std::string& name) const;   // the id of the light with this name
    std::vector<int> ids() const;
    std::vector<int> dirty() const { return {dirty_.begin(), dirty_.end()}; }

    // The scene as edited: its lights in id order.
    Scene scene() const;

    // Brings every stage but the march up to date for the edited scene (`frame` as in
    // Renderer::render) and reports what that took.
    LightRigUpdate apply(std::optional<int> frame = std::nullopt);

private:
    Light& at(int id);

    Renderer& renderer_;
    Scene scene_;                 // everything but the lights
    std::map<int, Light> lights_;
    std::set<int> dirty_;
    int next_id_ = 0;
};

}  // namespace voxlux
