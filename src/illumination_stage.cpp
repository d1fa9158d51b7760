#include "illumination_stage.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/parallel_for.h>

#include "light_sweeps.h"
#include "scene_json.h"

namespace voxlux {
namespace {

// A grid the sweeps run over: the light grid, or its chroma-subsampled coarsening.
struct SweepGrid {
    glm::mat4 grid_to_world{1.0f};
    glm::mat4 world_to_grid{1.0f};
    glm::ivec3 dims{0};
    float cells_per_voxel = 1.0f;          // grid cells per index voxel (for displacement)
    const std::vector<float>* sigma = nullptr;
};

glm::ivec3 coarserDims(glm::ivec3 d, int factor) { return (d + factor - 1) / factor; }

// The light grid's extinction averaged over blocks of 2^3 cells; cells past an odd edge count as
// empty space, which is what they are.
std::vector<float> halveGrid(const LightGrid& g) {
    const glm::ivec3 h = coarserDims(g.dims, 2);
    std::vector<float> out(size_t(h.x) * h.y * h.z, 0.0f);
    tbb::parallel_for(0, h.z, [&](int z) {
        for (int y = 0; y < h.y; ++y)
            for (int x = 0; x < h.x; ++x) {
                float sum = 0.0f;
                for (int k = 0; k < 8; ++k) {
                    const glm::ivec3 c = 2 * glm::ivec3(x, y, z) + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
                    if (glm::all(glm::lessThan(c, g.dims))) sum += g.values[(size_t(c.z) * g.dims.y + c.y) * g.dims.x + c.x];
                }
                out[(size_t(z) * h.y + y) * h.x + x] = sum * 0.125f;
            }
    });
    return out;
}

// What the sweeps of one light share on one grid.
kernel::VxPropParams baseParams(const SweepGrid& g, int channels, const std::vector<glm::vec4>& taps, float tan_half,
                                glm::vec3 atten) {
    kernel::VxPropParams Q{};
    Q.grid_to_world = g.grid_to_world;
    Q.world_to_grid = g.world_to_grid;
    Q.dims = glm::ivec4(g.dims, channels);
    Q.slice.w = int(taps.size());
    for (size_t k = 0; k < taps.size(); ++k) Q.taps[k] = taps[k];
    Q.flow = glm::vec4(1.0f, tan_half, 1.0f, 0.0f);
    Q.atten = glm::vec4(atten, g.cells_per_voxel);
    return Q;
}

// Moves a source position onto or behind the face the sweep enters through, so that every cell's
// flow points the way the slices advance (Ropinski: a light inside the volume is projected onto
// F0).
glm::vec3 behindEntryFace(glm::vec3 source, const Sweep& s, glm::ivec3 dims) {
    if (s.sign > 0) source[s.axis] = std::min(source[s.axis], 0.0f);
    else source[s.axis] = std::max(source[s.axis], float(dims[s.axis]));
    return source;
}

// Every sweep of one light on one grid: the principal axis, and with blending the second.
void sweepLight(const kernel::VxLight& light, const SweepGrid& g, kernel::VxPropParams Q, bool blend, SweepJob job,
                KernelBackend& backend, IlluminationVolume& volume) {
    const bool directional = int(light.pos_type.w) == VX_LIGHT_DIRECTIONAL;
    const glm::vec3 at = glm::vec3(g.world_to_grid * glm::vec4(glm::vec3(light.pos_type), 1.0f));
    const glm::vec3 flow =
        directional ? glm::mat3(g.world_to_grid) * glm::vec3(light.dir_cos) : 0.5f * glm::vec3(g.dims) - at;
    for (const Sweep& s : sweepsFor(flow, blend)) {
        Q.slice = glm::ivec4(s.axis, s.sign, 0, Q.slice.w);
        Q.flow.z = s.weight;
        Q.light = light;
        if (directional) {
            Q.source = glm::vec4(flow, 0.0f);
        } else {
            const glm::vec3 source = behindEntryFace(at, s, g.dims);
            Q.source = glm::vec4(source, 1.0f);
            Q.light.pos_type = glm::vec4(glm::vec3(g.grid_to_world * glm::vec4(source, 1.0f)), light.pos_type.w);
        }
        job.params = Q;
        job.sigma = g.sigma;
        backend.propagate(job, volume);
    }
}

// The light sweeps of every light: direct luminance on the fine grid, indirect RGB on the
// coarse one (the same grid unless chroma subsampled).
void propagateLights(const Effects& fx, const KernelInputs& inputs, const SweepGrid& fine, const SweepGrid& coarse,
                     KernelBackend& backend, IlluminationVolume& volume) {
    SweepJob job;
    job.march = &inputs.params;
    job.noise = &inputs.noise;
    const kernel::VxPropParams direct = baseParams(fine, 1, directTaps(), 0.0f, glm::vec3(1.0f));
    kernel::VxPropParams blurred{};
    if (fx.indirect)
        blurred = baseParams(coarse, 3, blurTaps(*fx.indirect), std::tan(glm::radians(0.5f * fx.indirect->angle)),
                             -glm::log(fx.indirect->transport_color));
    for (const auto& light : inputs.lights) {
        job.offset = 0;
        sweepLight(light, fine, direct, fx.propagation.blend_axes, job, backend, volume);
        if (!fx.indirect) continue;
        job.offset = volume.indirectOffset();
        sweepLight(light, coarse, blurred, fx.propagation.blend_axes, job, backend, volume);
    }
}

// The eye sweep (Ropinski Sec. 4.1): the indirect light flows towards the camera along the axis
// facing it. It reads `before`, the light sweeps' indirect block, and replaces the volume's.
void sweepTowardsEye(const Indirect& in, const KernelInputs& inputs, const SweepGrid& coarse, glm::vec3 eye_position,
                     const std::vector<float>& before, KernelBackend& backend, IlluminationVolume& volume) {
    const glm::vec3 cam = glm::vec3(coarse.world_to_grid * glm::vec4(eye_position, 1.0f));
    const Sweep s = sweepsFor(cam - 0.5f * glm::vec3(coarse.dims), false)[0];
    const float tan_half = std::tan(glm::radians(0.5f * in.angle));
    kernel::VxPropParams Q = baseParams(coarse, 3, blurTaps(in), tan_half, glm::vec3(1.0f));
    // The camera must be beyond the face the sweep leaves through.
    glm::vec3 source = cam;
    if (s.sign > 0) source[s.axis] = std::max(source[s.axis], float(coarse.dims[s.axis]));
    else source[s.axis] = std::min(source[s.axis], 0.0f);
    Q.slice = glm::ivec4(s.axis, s.sign, 0, Q.slice.w);
    Q.source = glm::vec4(source, 1.0f);
    Q.flow = glm::vec4(-1.0f, tan_half, 1.0f, 1.0f);
    SweepJob job;
    job.params = Q;
    job.march = &inputs.params;
    job.noise = &inputs.noise;
    job.sigma = coarse.sigma;
    job.offset = volume.indirectOffset();
    job.input = &before;
    backend.propagate(job, volume);
}

}  // namespace

size_t illuminationBytes(glm::ivec3 d, bool indirect, int chroma, bool eye_pass) {
    const size_t cells = size_t(d.x) * d.y * d.z;
    size_t bytes = cells * (sizeof(float) + 1 + sizeof(float));   // light grid, its mask, luminance
    if (indirect) {
        const glm::ivec3 c = coarserDims(d, chroma);
        const size_t cc = size_t(c.x) * c.y * c.z;
        bytes += cc * 3 * sizeof(float) * (eye_pass ? 2 : 1) + (chroma > 1 ? cc * sizeof(float) : 0);
    }
    return bytes;
}

void IlluminationStage::update(const Scene& scene, const Camera& camera, const std::string& volume_key,
                               KernelInputs& inputs, KernelBackend& backend, StageTimes& times,
                               std::vector<std::string>& reused, std::vector<std::string>& warnings) {
    const Effects& fx = scene.effects;
    const bool indirect = fx.indirect.has_value();
    const int chroma = indirect && fx.propagation.chroma_subsampling ? 2 : 1;
    const bool eye = indirect && fx.propagation.eye_pass;

    const glm::vec3 extent = occupiedExtent(inputs);
    const GridCost cost{[&](glm::ivec3 d) { return illuminationBytes(d, indirect, chroma, eye); },
                        [](glm::ivec3 d) { return uint64_t(d.x) * d.y * d.z * 4 < uint64_t(INT32_MAX); },
                        "illumination volume"};
    std::string warning;
    const int resolution = fitGridResolution(extent, cappedLightResolution(extent, fx.light_resolution),
                                             size_t(fx.light_memory_mb) << 20, cost, "illumination volume", warning);
    if (!warning.empty()) warnings.push_back(warning);

    const nlohmann::json sj = sceneToJson(scene);
    const std::string grid_key = volume_key + "|" + sj["material"].dump() + "|" + std::to_string(resolution);
    StageClock clock(times);
    if (grid_key == grid_key_) {
        reused.push_back("light_grid");
    } else {
        grid_key_.clear();  // all stay cleared if a pass throws
        light_key_.clear();
        eye_key_.clear();
        grid_ = clock("light_grid", [&] { return buildLightGrid(inputs, resolution, 0.0f); });
        if (grid_.clamped_cells) warnings.push_back(clampedCellsWarning(grid_));
        chroma_sigma_.clear();
        grid_key_ = grid_key;
    }

    SweepGrid fine;
    fine.grid_to_world = inputs.atlas->index_to_world * grid_.lightToIndex();
    fine.world_to_grid = glm::inverse(fine.grid_to_world);
    fine.dims = grid_.dims;
    fine.cells_per_voxel = 1.0f / grid_.cell;
    fine.sigma = &grid_.values;
    SweepGrid coarse = fine;
    if (chroma > 1) {
        if (chroma_sigma_.empty()) chroma_sigma_ = halveGrid(grid_);
        coarse.grid_to_world = fine.grid_to_world * glm::scale(glm::mat4(1.0f), glm::vec3(float(chroma)));
        coarse.world_to_grid = glm::inverse(coarse.grid_to_world);
        coarse.dims = coarserDims(grid_.dims, chroma);
        coarse.cells_per_voxel = fine.cells_per_voxel / float(chroma);
        coarse.sigma = &chroma_sigma_;
    }

    // The light sweeps depend on the lights and knobs, the eye sweep on the camera as well: a camera
    // move re-runs only the eye sweep, from the light sweeps' indirect block kept for it.
    const auto& P = inputs.params;
    nlohmann::json knobs = sj["effects"]["propagation"];
    knobs.erase("eye_pass");
    const std::string light_key = grid_key_ + "|" + sj["lights"].dump() + "|" + knobs.dump() + "|" +
                                  sj["effects"]["indirect"].dump() + "|" + sj["effects"]["perturbation"].dump() + "|" +
                                  std::to_string(P.noise_offset.x) + "," + std::to_string(P.noise_offset.y) + "," +
                                  std::to_string(P.noise_offset.z);
    const glm::vec3 eye_position(P.camera_to_world[3]);
    const std::string eye_key = !eye ? "" : light_key + "|eye " + std::to_string(eye_position.x) + "," +
                                                std::to_string(eye_position.y) + "," + std::to_string(eye_position.z);
    if (light_key == light_key_) {
        reused.push_back("propagation");
    } else {
        light_key_.clear();  // stays cleared if a pass throws
        eye_key_.clear();
        clock("propagation", [&] {
            volume_.dims = grid_.dims;
            volume_.chroma = chroma;
            volume_.chroma_dims = indirect ? coarse.dims : glm::ivec3(0);
            volume_.world_to_illum = fine.world_to_grid;
            volume_.values.assign(volume_.cells() + 3 * volume_.chromaCells(), 0.0f);
            propagateLights(fx, inputs, fine, coarse, backend, volume_);
        });
        before_eye_.clear();
        light_key_ = light_key;
    }
    if (eye_key != eye_key_) {
        const auto indirect_block = volume_.values.begin() + long(volume_.indirectOffset());
        if (before_eye_.empty()) before_eye_.assign(indirect_block, volume_.values.end());
        eye_key_.clear();
        if (eye) clock("eye_pass", [&] { sweepTowardsEye(*fx.indirect, inputs, coarse, eye_position, before_eye_, backend, volume_); });
        else std::copy(before_eye_.begin(), before_eye_.end(), indirect_block);   // the eye pass turned off
        eye_key_ = eye_key;
    } else if (eye) {
        reused.push_back("eye_pass");
    }

    auto& Pm = inputs.params;
    Pm.world_to_illum = volume_.world_to_illum;
    Pm.illum_dims = glm::ivec4(volume_.dims, volume_.chroma);
    Pm.chroma_dims = glm::ivec4(volume_.chroma_dims, int(volume_.indirectOffset()));
    inputs.illum = volume_.values.data();
    inputs.illum_floats = volume_.values.size();
}

}  // namespace voxlux
