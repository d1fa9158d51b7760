#include "illumination_stage.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/parallel_for.h>

#include "cpu_kernel.h"
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

// Rec. 709 luminance, as the kernel weighs it.
float luminance(glm::vec3 c) { return kernel::CpuKernel().vx_luminance(c); }

// What the sweeps of every light share on one grid.
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
    Q.tint = glm::vec4(1.0f);
    return Q;
}

// The sweeps of a set of lights, grouped by the pass that carries them: index 2 * axis + (sign > 0).
using PassSweeps = std::array<std::vector<kernel::VxPropParams>, 6>;

// Adds the sweeps of `light` on grid g to `passes`, weighted by `sign` (+1 adds the light, -1
// takes it out). Direct sweeps carry luminance and are tinted back to the light's colour.
void addLightSweeps(const kernel::VxLight& light, float sign, const SweepGrid& g, kernel::VxPropParams Q, bool blend,
                    PassSweeps& passes) {
    const glm::vec3 color(light.color);
    if (Q.dims.w == 1) {
        const float y = luminance(color);
        if (!(y > 0.0f)) return;   // a black light adds nothing
        Q.tint = glm::vec4(color / y, 0.0f);
    } else if (color == glm::vec3(0.0f)) {
        return;
    }
    Q.light = light;
    const bool directional = int(light.pos_type.w) == VX_LIGHT_DIRECTIONAL;
    std::vector<Sweep> sweeps;
    if (directional) {
        const glm::vec3 flow = glm::mat3(g.world_to_grid) * glm::vec3(light.dir_cos);
        Q.source = glm::vec4(flow, 0.0f);
        sweeps = sweepsFor(flow, blend);
    } else {
        const glm::vec3 at = glm::vec3(g.world_to_grid * glm::vec4(glm::vec3(light.pos_type), 1.0f));
        Q.source = glm::vec4(at, 1.0f);
        // The cells a sweep weights lie within slope 1 of the light (16 for a blended second
        // axis). A cell reads the previous slice up to 1 + r cells beside its own ray (bilinear
        // reads, blur radius r per slice, at most sqrt(3) tan(angle / 2)), so dark cells beyond
        // slope s creep inwards by at most 1 + r cells per slice while the weighted region grows
        // by 1: computing up to slope 2 + r keeps every weighted cell exact (3 + r, with margin).
        const int reach = blend ? int(VX_PROP_MAX_SLOPE) : 3 + int(std::ceil(std::sqrt(3.0f) * Q.flow.y));
        Q.mode = glm::ivec4(1, blend ? 1 : 0, reach, 0);
        sweeps = pointLightSweeps(at, g.dims, blend);
        if (int(light.pos_type.w) == VX_LIGHT_SPOT && !blend)
            sweeps = spotLightSweeps(sweeps, glm::vec3(light.dir_cos), light.dir_cos.w, glm::mat3(g.world_to_grid));
    }
    for (const Sweep& s : sweeps) {
        Q.slice = glm::ivec4(s.axis, s.sign, 0, Q.slice.w);
        Q.flow.z = sign * s.weight;
        passes[size_t(2 * s.axis + (s.sign > 0))].push_back(Q);
    }
}

// Lights whose sweeps differ only in colour and weight (directional lights along one direction,
// point lights at one place with one cone) see the same transmittance: each carries its colour
// times one propagated field. The sweep is linear in the light that enters, so they run as one
// sweep of a white light tinted by their weighted colours, exactly. This also makes a colour or
// intensity edit one sweep (old and new merge into their difference).
std::vector<kernel::VxPropParams> mergeSharedGeometry(const std::vector<kernel::VxPropParams>& sweeps) {
    auto geometry = [](kernel::VxPropParams Q) {
        Q.light.color = glm::vec4(0.0f, 0.0f, 0.0f, Q.light.color.w);   // w: the spot cone, geometry
        Q.tint = glm::vec4(0.0f);
        Q.flow.z = 0.0f;
        return Q;
    };
    std::vector<kernel::VxPropParams> shapes;   // one per geometry
    std::vector<std::vector<size_t>> members;
    for (size_t n = 0; n < sweeps.size(); ++n) {
        const kernel::VxPropParams g = geometry(sweeps[n]);
        size_t k = 0;
        while (k < shapes.size() && std::memcmp(&g, &shapes[k], sizeof g) != 0) ++k;
        if (k == shapes.size()) {
            shapes.push_back(g);
            members.emplace_back();
        }
        members[k].push_back(n);
    }
    std::vector<kernel::VxPropParams> out;
    for (size_t k = 0; k < shapes.size(); ++k) {
        if (members[k].size() == 1) {   // a lone sweep keeps its own form
            out.push_back(sweeps[members[k][0]]);
            continue;
        }
        kernel::VxPropParams Q = shapes[k];
        Q.light.color = glm::vec4(1.0f, 1.0f, 1.0f, Q.light.color.w);   // luminance 1
        Q.flow.z = 1.0f;
        for (size_t n : members[k]) Q.tint += glm::vec4(sweeps[n].flow.z * glm::vec3(sweeps[n].light.color), 0.0f);
        out.push_back(Q);
    }
    return out;
}

// What `passes` cost on grid g, in cells times the work of one directional direct sweep (the
// weights of SweepCost).
double passesCost(const PassSweeps& passes, const SweepGrid& g, bool coherent) {
    const double cells = double(g.dims.x) * g.dims.y * g.dims.z;
    double cost = 0.0;
    for (const auto& pass : passes) {
        if (pass.empty()) continue;
        const std::vector<kernel::VxPropParams> sweeps = coherent ? mergeSharedGeometry(pass) : pass;
        double own = SweepCost::kPass * double(coherent ? 1 : sweeps.size());
        for (const kernel::VxPropParams& Q : sweeps)
            own += (Q.mode.x != 0 ? SweepCost::kPointSweep : 1.0) * (Q.dims.w == 3 ? SweepCost::kIndirect : 1.0);
        cost += own * (sweeps.front().slice.x == 0 ? SweepCost::kXAxis : 1.0);
    }
    return cost * cells;
}

// Runs `passes` on grid g into the block at `offset`: one pass per direction with every light in
// it (coherent), or one pass per light sweep. Counts what ran into `report`.
void runPasses(const PassSweeps& passes, const SweepGrid& g, size_t offset, bool coherent, const KernelInputs& inputs,
               KernelBackend& backend, IlluminationVolume& volume, LightUpdate& report) {
    PropagationPass pass;
    pass.march = &inputs.params;
    pass.noise = &inputs.noise;
    pass.sigma = g.sigma;
    pass.offset = offset;
    for (const auto& sweeps : passes) {
        if (sweeps.empty()) continue;
        const int slices = g.dims[sweeps.front().slice.x];
        if (coherent) {
            pass.sweeps = mergeSharedGeometry(sweeps);
            report.sweeps += int(pass.sweeps.size());
            backend.propagate(pass, volume);
            report.passes += 1;
            report.slices += slices;
            continue;
        }
        report.sweeps += int(sweeps.size());
        for (const kernel::VxPropParams& Q : sweeps) {
            pass.sweeps = {Q};
            backend.propagate(pass, volume);
            report.passes += 1;
            report.slices += slices;
        }
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
    PropagationPass pass;
    pass.sweeps = {Q};
    pass.march = &inputs.params;
    pass.noise = &inputs.noise;
    pass.sigma = coarse.sigma;
    pass.offset = volume.indirectOffset();
    pass.input = &before;
    backend.propagate(pass, volume);
}

// The brightest radiance a light brings into the grid (luminance): what its sweeps add at most,
// and so what adding and later subtracting it can leave behind as float residue.
double peakRadiance(const kernel::VxLight& light, const SweepGrid& g) {
    const double y = luminance(glm::vec3(light.color));
    if (int(light.pos_type.w) == VX_LIGHT_DIRECTIONAL) return y;
    const glm::vec3 at = glm::vec3(g.world_to_grid * glm::vec4(glm::vec3(light.pos_type), 1.0f));
    const glm::vec3 nearest = glm::clamp(at, glm::vec3(0.0f), glm::vec3(g.dims));
    const double d = glm::length(glm::mat3(g.grid_to_world) * (at - nearest));
    const double r_min = 0.5 * glm::length(glm::vec3(g.grid_to_world[0]));
    return y / std::max(d * d, r_min * r_min);
}

bool sameLight(const kernel::VxLight& a, const kernel::VxLight& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The lights of `from` that `to` lacks, as a multiset: an unchanged light cancels however the list
// was reordered.
std::vector<kernel::VxLight> missingFrom(const std::vector<kernel::VxLight>& from, const std::vector<kernel::VxLight>& to) {
    std::vector<bool> used(to.size(), false);
    std::vector<kernel::VxLight> out;
    for (const auto& l : from) {
        size_t k = 0;
        while (k < to.size() && (used[k] || !sameLight(l, to[k]))) ++k;
        if (k < to.size()) used[k] = true;
        else out.push_back(l);
    }
    return out;
}

}  // namespace

size_t illuminationBytes(glm::ivec3 d, bool indirect, int chroma, bool eye_pass) {
    const size_t cells = size_t(d.x) * d.y * d.z;
    // The light grid, its mask, the direct RGB, and an x pass's slice-major copies of the
    // extinction and of its RGB result (CPU).
    size_t bytes = cells * (sizeof(float) + 1 + 3 * sizeof(float) + 4 * sizeof(float));
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
                        // The kernels index the volume (3 + 3 floats per cell at most) with ints.
                        [](glm::ivec3 d) { return uint64_t(d.x) * d.y * d.z * 6 < uint64_t(INT32_MAX); },
                        "illumination volume"};
    std::string warning;
    const int resolution = fitGridResolution(extent, cappedLightResolution(extent, fx.light_resolution),
                                             size_t(fx.light_memory_mb) << 20, cost, "illumination volume", warning);
    if (!warning.empty()) warnings.push_back(warning);

    const nlohmann::json sj = sceneToJson(scene);
    const std::string grid_key =
        volume_key + "|" + sj["material"].dump() + "|" + std::to_string(resolution) + "|" + occupiedBoxKey(inputs);
    StageClock clock(times);
    if (grid_key == grid_key_) {
        reused.push_back("light_grid");
    } else {
        grid_key_.clear();  // all stay cleared if a pass throws
        setup_key_.clear();
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

    // The light sweeps depend on the knobs and lights, the eye sweep on the camera as well: a camera
    // move re-runs only the eye sweep, from the light sweeps' indirect block kept for it.
    const auto& P = inputs.params;
    nlohmann::json knobs = sj["effects"]["propagation"];
    knobs.erase("eye_pass");
    knobs.erase("coherent");
    const std::string setup_key = grid_key_ + "|" + knobs.dump() + "|" + sj["effects"]["indirect"].dump() + "|" +
                                  sj["effects"]["perturbation"].dump() + "|" + std::to_string(P.noise_offset.x) + "," +
                                  std::to_string(P.noise_offset.y) + "," + std::to_string(P.noise_offset.z);
    const bool coherent = fx.propagation.coherent;
    const bool blend = fx.propagation.blend_axes;
    const kernel::VxPropParams direct = baseParams(fine, 1, directTaps(), 0.0f, glm::vec3(1.0f));
    kernel::VxPropParams blurred{};
    if (indirect)
        blurred = baseParams(coarse, 3, blurTaps(*fx.indirect), std::tan(glm::radians(0.5f * fx.indirect->angle)),
                             -glm::log(fx.indirect->transport_color));
    // The sweeps of `lights`, weighted by `sign`, on both blocks.
    auto sweepsOf = [&](const std::vector<kernel::VxLight>& lights, float sign, PassSweeps& fine_passes, PassSweeps& coarse_passes) {
        for (const auto& l : lights) {
            addLightSweeps(l, sign, fine, direct, blend, fine_passes);
            if (indirect) addLightSweeps(l, sign, coarse, blurred, blend, coarse_passes);
        }
    };
    auto estimate = [&](const PassSweeps& f, const PassSweeps& c) {
        return passesCost(f, fine, coherent) + passesCost(c, coarse, coherent);
    };
    auto peak = [&](const std::vector<kernel::VxLight>& lights) {
        double sum = 0.0;
        for (const auto& l : lights) sum += peakRadiance(l, fine);
        return sum;
    };

    LightUpdate report;
    report.lights = int(inputs.lights.size());
    PassSweeps all_fine, all_coarse;
    sweepsOf(inputs.lights, 1.0f, all_fine, all_coarse);
    report.entire_cost = estimate(all_fine, all_coarse);
    bool selective = false;
    PassSweeps sel_fine, sel_coarse;
    std::vector<kernel::VxLight> removed, added;
    if (setup_key != setup_key_) {
        report.reason = setup_key_.empty() ? "first update" : "the grid or the propagation settings changed";
    } else {
        removed = missingFrom(applied_, inputs.lights);
        added = missingFrom(inputs.lights, applied_);
        sweepsOf(removed, -1.0f, sel_fine, sel_coarse);
        sweepsOf(added, 1.0f, sel_fine, sel_coarse);
        report.selective_cost = estimate(sel_fine, sel_coarse);
        const double swept = drift_ + peak(removed) + peak(added);
        const double present = peak(inputs.lights);
        char why[200];
        if (removed.empty() && added.empty()) {
            report.mode = LightUpdate::Mode::Kept;
        } else if (swept > kDriftBudget * present) {
            std::snprintf(why, sizeof why, "re-base: light swept in and out since the last entire update (%.3g) exceeds %g x the light present (%.3g)",
                          swept, kDriftBudget, present);
            report.reason = why;
        } else {
            selective = report.selective_cost < report.entire_cost;
            std::snprintf(why, sizeof why, "%zu out, %zu in: estimated cost %.3g selective %s %.3g entire", removed.size(),
                          added.size(), report.selective_cost, selective ? "<" : ">=", report.entire_cost);
            report.reason = why;
        }
    }

    if (report.mode == LightUpdate::Mode::Kept) {
        reused.push_back("propagation");
    } else {
        setup_key_.clear();  // stays cleared if a pass throws: the volume is then half updated
        eye_key_.clear();
        const auto indirect_block = volume_.values.begin() + long(volume_.indirectOffset());
        clock("propagation", [&] {
            if (selective) {
                // The eye sweep replaced the light sweeps' indirect block: update that block instead.
                if (!before_eye_.empty()) std::copy(before_eye_.begin(), before_eye_.end(), indirect_block);
                report.mode = LightUpdate::Mode::Selective;
                report.lights_out = int(removed.size());
                report.lights_in = int(added.size());
                runPasses(sel_fine, fine, 0, coherent, inputs, backend, volume_, report);
                if (indirect) runPasses(sel_coarse, coarse, volume_.indirectOffset(), coherent, inputs, backend, volume_, report);
                drift_ += peak(removed) + peak(added);
            } else {
                volume_.dims = grid_.dims;
                volume_.chroma = chroma;
                volume_.chroma_dims = indirect ? coarse.dims : glm::ivec3(0);
                volume_.world_to_illum = fine.world_to_grid;
                volume_.values.assign(3 * volume_.cells() + 3 * volume_.chromaCells(), 0.0f);
                report.mode = LightUpdate::Mode::Entire;
                report.lights_in = int(inputs.lights.size());
                runPasses(all_fine, fine, 0, coherent, inputs, backend, volume_, report);
                if (indirect) runPasses(all_coarse, coarse, volume_.indirectOffset(), coherent, inputs, backend, volume_, report);
                drift_ = 0.0;
            }
        });
        before_eye_.clear();
        applied_ = inputs.lights;
        ++lights_version_;
        setup_key_ = setup_key;
    }
    last_update_ = report;

    const glm::vec3 eye_position(P.camera_to_world[3]);
    const std::string eye_key = !eye ? "" : setup_key_ + "|" + std::to_string(lights_version_) + "|eye " +
                                                std::to_string(eye_position.x) + "," + std::to_string(eye_position.y) +
                                                "," + std::to_string(eye_position.z);
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
