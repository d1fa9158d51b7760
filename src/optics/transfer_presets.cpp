#include "optics/transfer_presets.h"

namespace voxlux {
namespace {

TransferRegion rectangle(const char* name, glm::vec2 value, glm::vec2 gradient, float fade, float extinction, glm::vec3 albedo) {
    TransferRegion r;
    r.name = name;
    r.value = value;
    r.gradient = gradient;
    r.fade = fade;
    r.extinction = extinction;
    r.albedo = albedo;
    return r;
}

TransferRegion triangle(const char* name, glm::vec2 a, glm::vec2 b, glm::vec2 c, float fade, float extinction, glm::vec3 albedo) {
    TransferRegion r;
    r.name = name;
    r.triangle = true;
    r.corners = {a, b, c};
    r.fade = fade;
    r.extinction = extinction;
    r.albedo = albedo;
    return r;
}

// CT, HU. Air (-1000) is never selected. The skin is the air-tissue boundary: Kniss's triangle,
// its apex at the boundary's middle value (-450 HU) and gradient 0, widening to the values between
// air and tissue at the steep gradients (up to 1000 HU/mm) a boundary has.
const TransferRegion kSkin = triangle("skin", {-450.0f, 0.0f}, {-900.0f, 1000.0f}, {0.0f, 1000.0f}, 0.3f, 0.4f, {0.95f, 0.75f, 0.65f});
const TransferRegion kFat = rectangle("fat", {-150.0f, -50.0f}, {0.0f, 100.0f}, 0.5f, 0.005f, {1.0f, 0.9f, 0.55f});
const TransferRegion kSoftTissue = rectangle("soft tissue", {20.0f, 80.0f}, {0.0f, 100.0f}, 0.5f, 0.01f, {0.85f, 0.4f, 0.35f});
const TransferRegion kBone = rectangle("bone", {300.0f, 3000.0f}, {0.0f, kAnyGradient}, 0.05f, 2.0f, {1.0f, 0.97f, 0.9f});

}  // namespace

const std::vector<TransferPreset>& transferPresets() {
    static const std::vector<TransferPreset> presets = {
        {"ct_tissue", "CT (HU): skin as a veil, fat and soft tissue faint, bone opaque", {kSkin, kFat, kSoftTissue, kBone}},
        {"ct_bone", "CT (HU): bone alone", {rectangle("bone", {300.0f, 3000.0f}, {0.0f, kAnyGradient}, 0.05f, 3.0f, {1.0f, 0.97f, 0.9f})}},
        {"mri_t1_head", "T1 MRI of a head, 8-bit (as grids/mri_head.vdb): skin as a veil, the brain beneath",
         {rectangle("skin", {10.0f, 45.0f}, {4.0f, 100.0f}, 0.4f, 0.05f, {0.95f, 0.72f, 0.6f}),
          rectangle("brain", {60.0f, 120.0f}, {0.0f, 14.0f}, 0.8f, 1.5f, {0.95f, 0.9f, 0.85f})}},
    };
    return presets;
}

const TransferPreset* findTransferPreset(const std::string& name) {
    for (const TransferPreset& p : transferPresets())
        if (p.name == name) return &p;
    return nullptr;
}

}  // namespace voxlux
