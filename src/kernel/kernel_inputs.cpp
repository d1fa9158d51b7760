#include "kernel/kernel_inputs.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "scene/camera.h"
#include "optics/noise_table.h"
#include "optics/transfer_function.h"

namespace voxlux {

namespace {

kernel::VxLight packLight(const Light& l) {
    kernel::VxLight k{};
    int type = l.type == LightType::Point ? VX_LIGHT_POINT : l.type == LightType::Spot ? VX_LIGHT_SPOT : VX_LIGHT_DIRECTIONAL;
    // Keys a type does not use stay zero, so equal lights pack to equal bytes (selective updates
    // compare them).
    const bool directional = type == VX_LIGHT_DIRECTIONAL, point = type == VX_LIGHT_POINT;
    k.position = directional ? glm::vec3(0.0f) : l.position;
    k.type = type;
    k.direction = point ? glm::vec3(0.0f, -1.0f, 0.0f) : glm::normalize(l.direction);
    k.cos_outer = point ? 1.0f : std::cos(glm::radians(l.cone_angle));
    k.color = kernel::vx_radiance_add(glm::vec3(0.0f), l.color * l.intensity);   // at most the float maximum
    k.cos_inner = point ? 1.0f : std::cos(glm::radians(std::max(0.0f, l.cone_angle - l.cone_softness)));
    return k;
}

// Extinction per world unit per unit of density under material `m` in a grid of voxel edge `edge`:
// per voxel length, the same look on a cache saved at any scale (at most the float maximum).
float densityScale(const Material& m, float edge) {
    return m.density_units == DensityUnits::Voxel ? std::min(m.density_scale / edge, std::numeric_limits<float>::max()) : m.density_scale;
}

// The grid value at a transfer function's table's first row, and 1 / the values its rows span (0
// to 1 without a transfer function).
float transferLow(const std::vector<TransferPoint>& tf) { return tf.empty() ? 0.0f : tf.front().value; }
float transferInverseRange(const std::vector<TransferPoint>& tf) { return tf.empty() ? 1.0f : 1.0f / (tf.back().value - tf.front().value); }

// Of several volumes, the index space the light grids and the lighting methods' lookups work in
// (in.index_to_world, P.world_to_index): aligned with the world axes, its voxel the finest
// volume's edge, its bricks (P.bricks_min to P.bricks_max) covering the box of all placed volumes
// but the mesh holdouts' cells (`cells`, per entry of in.volumes), which reach past it.
void setSharedFrame(KernelInputs& in, const std::vector<bool>& cells) {
    float edge = std::numeric_limits<float>::max();
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (size_t i = 0; i < in.volumes.size(); ++i) {
        if (cells[i]) continue;
        const glm::mat4 to_world = glm::inverse(in.volumes[i].world_to_index);
        edge = std::min(edge, voxelEdge(to_world));
        growByPageRange(in.volumes[i].pages, to_world, lo, hi);
    }
    if (lo.x > hi.x) lo = hi = glm::vec3(0.0f);
    in.index_to_world = glm::scale(glm::translate(glm::mat4(1.0f), lo), glm::vec3(edge));
    in.params.bricks_min = glm::ivec3(0);
    in.params.bricks_max = glm::max(glm::ivec3(glm::ceil((hi - lo) / (edge * float(VX_BRICK)))) - 1, glm::ivec3(0));
}

// The volumes of a scene of several, each instance placed at `frame` over its volume's range of
// the joined bricks. Their transfer functions' tables follow the one volume's in in.tf_lut.
void setVolumes(const Scene& scene, const SceneBricks& bricks, float frame, KernelInputs& in) {
    std::vector<glm::vec4> tables;
    std::vector<bool> cells;   // per entry of in.volumes: a mesh holdout's
    const LightLinks links = lightLinks(scene);
    for (size_t v = 0; v < scene.volumes.size(); ++v) {
        const VolumeSpec& spec = scene.volumes[v];
        const std::vector<TransferPoint>& transfer = spec.material.transfer;
        const int transfer_row = transfer.empty() ? -1 : VX_TF_LUT_SIZE + int(tables.size());
        if (!transfer.empty()) {
            const std::vector<glm::vec4> table = bakeTransfer(transfer);
            tables.insert(tables.end(), table.begin(), table.end());
        }
        for (const glm::mat4& placement : instancePlacements(spec, frame)) {
            const glm::mat4 index_to_world = placement * bricks.index_to_world[v];
            kernel::VxVolume k{};
            k.world_to_index = glm::inverse(index_to_world);
            k.pages = bricks.ranges[v];
            k.albedo = spec.material.albedo;
            k.density_scale = densityScale(spec.material, voxelEdge(index_to_world));
            k.anisotropy = spec.material.anisotropy;
            k.role = spec.role == VolumeRole::Matte ? VX_ROLE_MATTE : spec.role == VolumeRole::ShadowOnly ? VX_ROLE_SHADOW_ONLY : VX_ROLE_VISIBLE;
            k.transfer_row = transfer_row;
            k.transfer_lo = transferLow(transfer);
            k.transfer_inv_range = transferInverseRange(transfer);
            const VolumeChannels& c = bricks.channels[v];
            k.use_color = c.color ? 1 : 0;
            k.color_offset = c.color_offset;
            k.use_velocity = c.velocity ? 1 : 0;
            k.velocity_offset = c.velocity_offset;
            k.emission_first = c.emission_first;
            k.emission_count = c.emission_count;
            k.emission_offset = c.emission_offset;
            k.emission_stride = c.emission_stride;
            for (size_t set = 0; set < links.sets.size(); ++set) {
                const auto names = [&](const std::optional<std::vector<std::string>>& list) {
                    return !list || std::binary_search(list->begin(), list->end(), spec.name);
                };
                k.lit_sets |= names(links.sets[set].lit) ? 1 << set : 0;
                k.shadow_sets |= names(links.sets[set].shadows) ? 1 << set : 0;
            }
            in.params.volume_roles |= k.role != VX_ROLE_VISIBLE ? 1 : 0;
            in.volumes.push_back(k);
            cells.push_back(spec.holdout_mesh.has_value());
        }
    }
    in.tf_lut = std::move(tables);
    setSharedFrame(in, cells);
    if (in.volumes.size() > VX_MAX_VOLUMES)
        throw InputError(std::to_string(in.volumes.size()) + " volumes and instances: a scene places at most " + std::to_string(VX_MAX_VOLUMES) + " so far");
    in.params.volume_count = int(in.volumes.size());
}

// The length the march's steps are counted in: the voxel edge, of several volumes the finest.
float stepUnit(const KernelInputs& in) {
    float edge = voxelEdge(in.index_to_world);
    for (const kernel::VxVolume& v : in.volumes) edge = std::min(edge, voxelEdge(glm::inverse(v.world_to_index)));
    return edge;
}

// One emission source of the scene, the largest value of its grid in this frame, and whether its
// volume is seen (a matte's or a shadow-only volume's sources emit nothing).
struct SourceSpan {
    const EmissionSource* source;
    float grid_max;
    bool seen = true;
};

// The scene's emission sources in the kernel's numbering: the one volume's, or of several (their
// joined `volumes`) each volume's in turn.
std::vector<SourceSpan> emissionSources(const Scene& scene, const BrickAtlas& atlas, const SceneBricks* volumes) {
    std::vector<SourceSpan> out;
    if (!volumes) {
        for (size_t e = 0; e < atlas.emission_sources; ++e) out.push_back({&scene.volume().emission.at(e), atlas.emissionGridMax(e)});
        return out;
    }
    for (size_t v = 0; v < scene.volumes.size(); ++v)
        for (size_t s = 0; s < size_t(volumes->channels[v].emission_count); ++s)
            out.push_back({&scene.volumes[v].emission.at(s), volumes->emission_grid_max[size_t(volumes->channels[v].emission_first) + s],
                           scene.volumes[v].role == VolumeRole::Visible});
    return out;
}

// The medium: the march step, the material, the transfer function and the emission tables.
void setMedium(const Scene& scene, const BrickAtlas& atlas, const SceneBricks* volumes, const glm::mat3& xyz_to_working, KernelInputs& in) {
    auto& P = in.params;
    const auto& r = scene.render;
    const auto& m = scene.volume().material;
    const float edge = stepUnit(in);
    P.world_to_index = glm::inverse(in.index_to_world);
    P.step = r.step * edge;
    P.voxel_filter = r.filter == Filter::Tricubic ? VX_FILTER_TRICUBIC : VX_FILTER_TRILINEAR;
    P.deep_samples = scene.output.deep ? std::clamp(scene.output.deep_samples, 1, 64) : 0;   // a ray holds 65 (vx_deep.h)
    P.shadow_step = r.shadow_step * edge;
    P.transmittance_cutoff = r.transmittance_cutoff;
    P.anisotropy = m.anisotropy;
    P.albedo = m.albedo;
    P.density_scale = densityScale(m, voxelEdge(in.index_to_world));
    // Each source's table spans its grid's values in this frame's atlas. When none emits anywhere
    // (all-zero grids) the march runs as without emission, to the bit.
    bool emits = false;
    const std::vector<SourceSpan> sources = emissionSources(scene, atlas, volumes);
    for (size_t e = 0; e < sources.size(); ++e) {
        const float grid_max = sources[e].grid_max;
        const EmissionTable table = bakeEmission(*sources[e].source, grid_max, xyz_to_working);
        in.emission_lut.insert(in.emission_lut.end(), table.rows.begin(), table.rows.end());
        P.emission_domain[int(e)] = grid_max > 0.0f ? 1.0f / grid_max : 0.0f;
        emits |= sources[e].seen && table.threshold < std::numeric_limits<float>::infinity();
    }
    P.emission_sources = emits ? int(sources.size()) : 0;
    P.emission_source_floats = int(atlas.slots()) * VX_BRICK_VOXELS;
    P.transfer_lo = transferLow(m.transfer);
    P.transfer_inv_range = transferInverseRange(m.transfer);
    // Of several volumes, each volume's transfer function and colour are its own (VxVolume).
    P.use_transfer = m.transfer.empty() || volumes ? 0 : 1;
    P.use_color_grid = atlas.color.empty() || volumes ? 0 : 1;
    P.use_surface_grid = atlas.surface.empty() ? 0 : 1;
    P.surface_offset = int(atlas.color.size() + atlas.velocity.size());   // GL: after both in their block
    const std::vector<glm::vec4> own = bakeTransfer(volumes ? std::vector<TransferPoint>{} : m.transfer);
    in.tf_lut.insert(in.tf_lut.begin(), own.begin(), own.end());   // before the volumes' tables (setVolumes)
}

// The enabled lights, ambient ones summed into one radiance (and per light group), and how their
// shadows are found.
void setLights(const Scene& scene, KernelInputs& in) {
    auto& P = in.params;
    const LightGroups groups = lightGroups(scene);
    const LightLinks links = lightLinks(scene);
    in.group_ambient.assign(std::max<size_t>(groups.names.size(), 1), glm::vec3(0.0f));
    // Ambient lights are not shadowed and act the same everywhere: they sum into one radiance.
    glm::vec3 ambient(0.0f);
    int local_lights = 0;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        if (!l.enabled) continue;
        const int group = groups.names.empty() ? 0 : groups.of_light[i];
        // The reference samples an environment's map; the march takes its median-cut lights and
        // remainder, which withEnvironmentLights appended (src/render/environment_lights.h).
        if (l.type == LightType::Environment) {
            if (l.environment && l.environment->loaded) in.environments.push_back({l.environment->loaded, group, l.environment->visible_to_camera});
            continue;
        }
        if (l.type == LightType::Ambient) {
            ambient = kernel::vx_radiance_add(ambient, l.color * l.intensity);
            in.group_ambient[size_t(group)] = kernel::vx_radiance_add(in.group_ambient[size_t(group)], l.color * l.intensity);
            continue;
        }
        in.lights.push_back(packLight(l));
        in.lights.back().group = group;
        in.lights.back().link_set = links.of_light[i];
        local_lights += l.type != LightType::Directional;
    }
    P.ambient = ambient;
    P.has_ambient = glm::any(glm::greaterThan(ambient, glm::vec3(0.0f))) ? 1 : 0;
    P.shadow_rays = scene.effects.shadows == ShadowMethod::Raymarch ? 1 : 0;
    P.light_count = int(in.lights.size());
    P.link_sets = int(links.sets.size());
    P.local_light_count = local_lights;
}

// Kniss 2003's surface shading and perturbation.
void setKnissEffects(const Effects& fx, float edge, float frame, KernelInputs& in) {
    auto& P = in.params;
    if (const auto& sf = fx.surface) {
        P.surface_low = sf->gradient_low;
        // At most the float maximum: a range of 1e-45 made it infinite, and 0 x inf is NaN.
        P.surface_inv_range = std::min(1.0f / (sf->gradient_high - sf->gradient_low), VX_FLOAT_MAX);
        P.specular = sf->specular;
        P.shininess = sf->shininess;
    }
    // A perturbation of zero amplitude is no perturbation: it stays off, so the render is exactly
    // the unperturbed one and costs nothing.
    if (const auto& pt = fx.perturbation; pt && (pt->density > 0 || pt->transport > 0 || pt->displacement > 0)) {
        // Automatic: two voxels per texel of the first octave. It follows the voxel size, not the
        // data's extent, so a sequence whose extent changes frame to frame keeps its noise.
        const float scale = pt->scale > 0.0f ? pt->scale : 2.0f * float(VX_NOISE_SIZE) * edge;
        P.noise_frequency = float(VX_NOISE_SIZE) / scale;
        P.noise_octaves = pt->octaves;
        P.lacunarity = pt->lacunarity;
        P.gain = pt->gain;
        P.noise_offset = pt->velocity * (frame + pt->time);
        P.displacement = pt->displacement;
        P.noise_density = pt->density;
        P.noise_transport = pt->transport;
        in.noise = makeNoiseTable(pt->seed);
    }
}

// Velocity motion blur (vx_motion.h): the shutter, the velocity's units, and the camera's motion.
// Where neither the medium (a velocity grid of some speed) nor the camera moves, nothing blurs, and
// a pixel takes one ray.
void setMotionBlur(const Scene& scene, const BrickAtlas& atlas, const Camera* camera, KernelInputs& in) {
    auto& P = in.params;
    P.time_samples = 1;
    const auto& mb = scene.render.motion_blur;
    if (!mb) return;
    const bool camera_moves = camera && camera->motion;
    P.use_velocity = atlas.velocity.empty() || atlas.motion_reach == 0 ? 0 : 1;
    P.velocity_offset = int(atlas.color.size());
    if (!P.use_velocity && !camera_moves) return;
    P.motion_blur = 1;
    P.time_samples = mb->samples;
    P.velocity_per_frame = mb->velocity_scale / mb->fps;
    P.shutter_open = mb->shutter_open;
    P.shutter_close = mb->shutter_close;
    if (camera_moves) {
        P.camera_moves = 1;
        P.camera_open = (*camera->motion)[0];
        P.camera_close = (*camera->motion)[1];
    }
}

// Depth of field (vx_through_lens): the lens, and a pixel's rays spread over it too (as many as
// the shutter takes, at least the camera's lens_samples).
void setDepthOfField(const Camera* camera, KernelInputs& in) {
    if (!camera || lensRadius(*camera) <= 0.0f) return;
    in.params.lens_radius = lensRadius(*camera);
    in.params.focus_distance = camera->focus_distance;
    in.params.time_samples = std::max(in.params.time_samples, camera->lens_samples);
}

}  // namespace

void MarchLighting::setArray(const std::string& block, const void* data, size_t bytes) {
    std::erase_if(arrays, [&](const KernelArrayRef& a) { return a.block == block; });
    arrays.push_back({block, data, bytes});
}

KernelInputs makeKernelInputs(const Scene& scene, const BrickAtlas& atlas, const PageTable& pages, float frame,
                              const glm::mat3& xyz_to_working, const MarchSources& sources) {
    KernelInputs in;
    in.atlas = &atlas;
    in.pages = &pages;
    const glm::mat4 placement = volumePlacement(scene.volume(), frame);
    in.index_to_world = placement * atlas.index_to_world;
    auto& P = in.params;
    P.velocity_to_world = placement;   // velocities are the file's world units
    if (const Camera* camera = sources.camera) {
        P.camera_to_world = cameraToWorld(*camera);
        P.tan_half_fov = std::tan(glm::radians(camera->fov) * 0.5f);
        P.aspect = float(scene.render.width) / float(scene.render.height);
        P.width = scene.render.width;
        P.height = scene.render.height;
        in.region = regionPixels(scene.render, P.width, P.height);
    }
    P.bricks_min = pages.bricks_min;
    P.bricks_max = pages.bricks_max;
    P.page_capacity = pages.brick_capacity;
    P.page_max_probe = pages.max_probe;
    P.region_capacity = pages.region_capacity;
    P.region_max_probe = pages.region_max_probe;
    if (sources.volumes) setVolumes(scene, *sources.volumes, frame, in);   // and the shared frame
    setMedium(scene, atlas, sources.volumes, xyz_to_working, in);
    setLights(scene, in);
    in.lighting = sources.lighting;   // the methods' blocks and arrays, as their stages set them
    if (sources.holdout && !sources.holdout->empty()) {
        in.holdout = sources.holdout;
        P.holdout = 1;
        P.holdout_offset = int(atlas.color.size() + atlas.velocity.size() + atlas.surface.size());   // GL: after them in their block
    }
    P.ambient *= sources.lighting.ambient_scale;
    for (glm::vec3& a : in.group_ambient) a *= sources.lighting.ambient_scale;
    setKnissEffects(scene.effects, voxelEdge(in.index_to_world), frame, in);
    setMotionBlur(scene, atlas, sources.camera, in);
    setDepthOfField(sources.camera, in);
    return in;
}

}  // namespace voxlux
