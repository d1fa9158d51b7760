#include "render/light_rig.h"

#include <chrono>

#include "core/error.h"

namespace voxlux {

LightRig::LightRig(Renderer& renderer, Scene scene) : renderer_(renderer), scene_(std::move(scene)) {
    for (const Light& l : scene_.lights) lights_[next_id_++] = l;
    scene_.lights.clear();
}

Light& LightRig::at(int id) {
    auto it = lights_.find(id);
    if (it == lights_.end()) throw InputError("light rig: no light with id " + std::to_string(id));
    return it->second;
}

const Light& LightRig::light(int id) const { return const_cast<LightRig*>(this)->at(id); }

int LightRig::add(const Light& light) {
    lights_[next_id_] = light;
    dirty_.insert(next_id_);
    return next_id_++;
}

void LightRig::remove(int id) {
    at(id);
    lights_.erase(id);
    dirty_.insert(id);
}

void LightRig::update(int id, const Light& light) {
    at(id) = light;
    dirty_.insert(id);
}

void LightRig::toggle(int id, bool on) {
    at(id).enabled = on;
    dirty_.insert(id);
}

std::optional<int> LightRig::find(const std::string& name) const {
    for (const auto& [id, l] : lights_)
        if (l.name == name) return id;
    return std::nullopt;
}

std::vector<int> LightRig::ids() const {
    std::vector<int> out;
    for (const auto& entry : lights_) out.push_back(entry.first);
    return out;
}

Scene LightRig::scene() const {
    Scene s = scene_;
    for (const auto& entry : lights_) s.lights.push_back(entry.second);
    return s;
}

LightRigUpdate LightRig::apply(std::optional<int> frame) {
    LightRigUpdate out;
    out.dirty = dirty();
    renderer_.setScene(scene());
    const auto start = std::chrono::steady_clock::now();
    FrameResult r = renderer_.prepare(frame, true);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.lighting = r.light_update;
    out.stage_seconds = r.stage_seconds;
    dirty_.clear();
    return out;
}

}  // namespace voxlux
