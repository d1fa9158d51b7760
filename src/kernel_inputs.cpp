#include "kernel_inputs.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "camera.h"
#include "noise_table.h"
#include "transfer_function.h"

namespace voxlux {

float voxelEdge(const glm::mat4& m) {
    return std::min({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
}

namespace {

kernel::VxLight packLight(const Light& l) {
    kernel::VxLight k{};
    int type = l.type == LightType::Point ? VX_LIGHT_POINT : l.type == LightType::Spot ? VX_LIGHT_SPOT : VX_LIGHT_DIRECTIONAL;
    // Keys a type does not use stay zero, so equal lights pack to equal bytes (selective updates
    // compare them).
    const bool directional = type == VX_LIGHT_DIRECTIONAL, point = type == VX_LIGHT_POINT;
    k.pos_type = glm::vec4(directional ? glm::vec3(0.0f) : l.position, float(type));
    k.dir_cos = point ? glm::vec4(0.0f, -1.0f, 0.0f, 1.0f) : glm::vec4(glm::normalize(l.direction), std::cos(glm::radians(l.cone_angle)));
    k.color = glm::vec4(l.color * l.intensity, point ? 1.0f : std::cos(glm::radians(std::max(0.0f, l.cone_angle - l.cone_softness))));
    return k;
}

}  // namespace

KernelInputs makeKernelInputs(const Scene& scene, const BrickAtlas& atlas, const PageTable& pages, float frame,
                              const glm::mat3& xyz_to_working, const MarchSources& sources) {
    KernelInputs in;
    in.atlas = &atlas;
    in.pages = &pages;
    auto& P = in.params;
    const auto& r = scene.render;
    const auto& m = scene.material;
    float edge = voxelEdge(atlas.index_to_world);
    if (const Camera* camera = sources.camera) {
        P.camera_to_world = cameraToWorld(*camera);
        P.camera_frame = glm::vec4(std::tan(glm::radians(camera->fov) * 0.5f), float(r.width) / float(r.height),
                                   float(r.width), float(r.height));
    }
    P.world_to_index = glm::inverse(atlas.index_to_world);
    P.march = glm::vec4(r.step * edge, r.shadow_step * edge, r.transmittance_cutoff, m.anisotropy);
    P.material = glm::vec4(m.albedo, m.density_scale);
    // Each source's table spans its grid's values in this frame's atlas. When none emits anywhere
    // (all-zero grids) the march runs as without emission, to the bit.
    bool emits = false;
    for (size_t e = 0; e < atlas.emission_sources; ++e) {
        const float grid_max = atlas.emissionGridMax(e);
        const EmissionTable table = bakeEmission(scene.emission.at(e), grid_max, xyz_to_working);
        in.emission_lut.insert(in.emission_lut.end(), table.rows.begin(), table.rows.end());
        P.emission_domain[int(e)] = grid_max > 0.0f ? 1.0f / grid_max : 0.0f;
        emits |= table.threshold < std::numeric_limits<float>::infinity();
    }
    P.emission_map = glm::ivec4(emits ? int(atlas.emission_sources) : 0, int(atlas.slots()) * VX_BRICK_VOXELS, 0, 0);
    float lo = m.transfer.empty() ? 0.0f : m.transfer.front().value;
    float hi = m.transfer.empty() ? 1.0f : m.transfer.back().value;
    P.tf_domain = glm::vec4(lo, 1.0f / (hi - lo), m.transfer.empty() ? 0.0f : 1.0f, atlas.color.empty() ? 0.0f : 1.0f);
    // Ambient lights are not shadowed and act the same everywhere: they sum into one radiance.
    glm::vec3 ambient(0.0f);
    int local_lights = 0;
    for (const auto& l : scene.lights) {
        if (!l.enabled) continue;
        if (l.type == LightType::Ambient) {
            ambient += l.color * l.intensity;
            continue;
        }
        in.lights.push_back(packLight(l));
        local_lights += l.type != LightType::Directional;
    }
    P.ambient = glm::vec4(ambient, glm::any(glm::greaterThan(ambient, glm::vec3(0.0f))) ? 1.0f : 0.0f);
    const int shadows = scene.effects.shadows == ShadowMethod::Raymarch      ? VX_SHADOWS_RAYMARCH
                        : scene.effects.shadows == ShadowMethod::SatCone     ? VX_SHADOWS_SAT_CONE
                        : scene.effects.shadows == ShadowMethod::Propagation ? VX_SHADOWS_PROPAGATION
                                                                             : VX_SHADOWS_NONE;
    P.bricks_min = glm::ivec4(pages.bricks_min, int(in.lights.size()));
    P.bricks_max = glm::ivec4(pages.bricks_max, shadows);
    P.page = glm::ivec4(int(pages.entries.size()), pages.max_probe, local_lights, 0);
    in.tf_lut = bakeTransfer(m.transfer);

    P.cache_dims = glm::ivec4(0);
    P.cache_map = glm::ivec4(-1, 1, -1, 0);
    if (const LightCache* c = sources.light_cache; c && c->channels > 0) {
        in.light_cache = c;
        P.world_to_cache = c->world_to_cache;
        P.cache_dims = glm::ivec4(c->dims, c->channels);
        P.cache_map = glm::ivec4(c->ambient_channel, c->ambient_width, c->shadow_channel, 0);
    }
    P.illum_dims = glm::ivec4(0, 0, 0, 1);
    if (const IlluminationVolume* v = sources.illumination; v && !v->values.empty()) {
        in.illumination = v;
        P.world_to_illum = v->world_to_illum;
        P.illum_dims = glm::ivec4(v->dims, v->chroma);
        P.chroma_dims = glm::ivec4(v->chroma_dims, int(v->indirectOffset()));
    }
    if (const auto& ind = scene.effects.indirect; ind && scene.effects.shadows == ShadowMethod::Propagation)
        P.indirect = glm::vec4(ind->transport_color, ind->strength / (4.0f * float(M_PI)));
    if (const auto& sf = scene.effects.surface)
        P.surface = glm::vec4(sf->gradient_low, 1.0f / (sf->gradient_high - sf->gradient_low), sf->specular, sf->shininess);
    // A perturbation of zero amplitude is no perturbation: it stays off, so the render is exactly
    // the unperturbed one and costs nothing.
    if (const auto& pt = scene.effects.perturbation; pt && (pt->density > 0 || pt->transport > 0 || pt->displacement > 0)) {
        // Automatic: two voxels per texel of the first octave. It follows the voxel size, not the
        // data's extent, so a sequence whose extent changes frame to frame keeps its noise.
        const float scale = pt->scale > 0.0f ? pt->scale : 2.0f * float(VX_NOISE_SIZE) * edge;
        P.noise_scale = glm::vec4(float(VX_NOISE_SIZE) / scale, float(pt->octaves), pt->lacunarity, pt->gain);
        P.noise_offset = glm::vec4(pt->velocity * (frame + pt->time), pt->displacement);
        P.noise_amp = glm::vec4(pt->density, pt->transport, 0.0f, 0.0f);
        in.noise = makeNoiseTable(pt->seed);
    }
    return in;
}

}  // namespace voxlux
