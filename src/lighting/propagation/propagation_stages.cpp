#include "lighting/propagation/propagation_stages.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/parallel_for.h>

#include "kernel/medium_inputs.h"
#include "core/huge_pages.h"
#include "scene/camera.h"
#include "kernel/cpu_kernel_data.h"
#include "lighting/propagation/emitted_light.h"
#include "lighting/propagation/light_sweeps.h"
#include "optics/diffusion_profile.h"
#include "optics/transfer_function_2d.h"
#include "volume/volume_stages.h"

namespace voxlux {
namespace {

glm::ivec3 coarserDims(glm::ivec3 d, int factor) { return (d + factor - 1) / factor; }

// A grid of `channels` floats per cell over `dims` cells averaged over blocks of 2^3 cells; cells
// past an odd edge count as empty space, which is what they are.
std::vector<float> halveGrid(const float* values, glm::ivec3 dims, int channels) {
    const glm::ivec3 h = coarserDims(dims, 2);
    std::vector<float> out(size_t(h.x) * h.y * h.z * channels, 0.0f);
    tbb::parallel_for(0, h.z, [&](int z) {
        for (int y = 0; y < h.y; ++y)
            for (int x = 0; x < h.x; ++x)
                for (int ch = 0; ch < channels; ++ch) {
                    float sum = 0.0f;
                    for (int k = 0; k < 8; ++k) {
                        const glm::ivec3 c = 2 * glm::ivec3(x, y, z) + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
                        if (glm::all(glm::lessThan(c, dims)))
                            sum += values[((size_t(c.z) * dims.y + c.y) * dims.x + c.x) * channels + ch];
                    }
                    out[((size_t(z) * h.y + y) * h.x + x) * channels + ch] = sum * 0.125f;
                }
    });
    return out;
}

// Rec. 709 luminance, as the kernel weighs it.
float luminance(glm::vec3 c) { return kernel::CpuKernelData().vx_luminance(c); }

// The indirect light's profile per unit of light entering: diffusion theory's
// (src/optics/diffusion_profile.h), or Kniss's, attenuated by -ln(transport colour).
FluenceProfile indirectFluence(const Indirect& in, const Material& m) {
    if (in.model == IndirectModel::Diffusion) return collimatedFluence(m.albedo, m.anisotropy);
    return {glm::vec3(1.0f), -glm::log(in.transport_color)};
}

// What the sweeps of every light share on one grid.
kernel::VxPropParams baseParams(const SweepGrid& g, int channels, const std::vector<kernel::VxTap>& taps, float tan_half,
                                glm::vec3 atten) {
    kernel::VxPropParams Q{};
    Q.grid_to_world = g.grid_to_world;
    Q.world_to_grid = g.world_to_grid;
    Q.dims = g.dims;
    Q.channels = channels;
    Q.tap_count = int(taps.size());
    for (size_t k = 0; k < taps.size(); ++k) Q.taps[k] = taps[k];
    Q.flow = 1.0f;
    Q.blur_tan = tan_half;
    Q.weight = 1.0f;
    Q.atten = atten;
    Q.cells_per_voxel = g.cells_per_voxel;
    Q.tint = glm::vec3(1.0f);
    return Q;
}

// The sweeps of a set of lights, grouped by the pass that carries them: index 2 * axis + (sign > 0).
using PassSweeps = std::array<std::vector<kernel::VxPropParams>, 6>;

// Adds the sweeps of `light` on grid g to `passes`, weighted by `sign` (+1 adds the light, -1
// takes it out). Direct sweeps carry luminance and are tinted back to the light's colour.
void addLightSweeps(const kernel::VxLight& light, float sign, const SweepGrid& g, kernel::VxPropParams Q, bool blend,
                    PassSweeps& passes) {
    const glm::vec3 color = light.color;
    if (Q.channels == 1) {
        const float y = luminance(color);
        if (!(y > 0.0f)) return;   // a black light adds nothing
        Q.tint = color / y;
    } else if (color == glm::vec3(0.0f)) {
        return;
    }
    Q.light = light;
    std::vector<Sweep> sweeps;
    if (light.type == VX_LIGHT_DIRECTIONAL) {
        const glm::vec3 flow = glm::mat3(g.world_to_grid) * light.direction;
        Q.source = flow;
        Q.source_is_position = 0;
        sweeps = sweepsFor(flow, blend);
    } else {
        const glm::vec3 at = glm::vec3(g.world_to_grid * glm::vec4(light.position, 1.0f));
        Q.source = at;
        Q.source_is_position = 1;
        // The cells a sweep weights lie within slope 1 of the light (16 for a blended second
        // axis). A cell reads the previous slice up to 1 + r cells beside its own ray (bilinear
        // reads, blur radius r per slice, at most sqrt(3) tan(angle / 2)), so dark cells beyond
        // slope s creep inwards by at most 1 + r cells per slice while the weighted region grows
        // by 1: computing up to slope 2 + r keeps every weighted cell exact (3 + r, with margin).
        Q.max_slope = blend ? int(VX_PROP_MAX_SLOPE) : 3 + int(std::ceil(std::sqrt(3.0f) * Q.blur_tan));
        Q.per_cell_flow = 1;
        Q.blend_axes = blend ? 1 : 0;
        sweeps = pointLightSweeps(at, g.dims, blend);
        if (light.type == VX_LIGHT_SPOT && !blend)
            sweeps = spotLightSweeps(sweeps, light.direction, light.cos_outer, glm::mat3(g.world_to_grid));
    }
    for (const Sweep& s : sweeps) {
        Q.axis = s.axis;
        Q.direction = s.sign;
        Q.weight = sign * s.weight;
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
        Q.light.color = glm::vec3(0.0f);
        Q.tint = glm::vec3(0.0f);
        Q.weight = 0.0f;
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
        Q.light.color = glm::vec3(1.0f);   // luminance 1
        Q.weight = 1.0f;
        for (size_t n : members[k]) Q.tint += sweeps[n].weight * sweeps[n].light.color;
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
            own += (Q.per_cell_flow != 0 ? SweepCost::kPointSweep : 1.0) * (Q.channels == 3 ? SweepCost::kIndirect : 1.0);
        cost += own * (sweeps.front().axis == 0 ? SweepCost::kXAxis : 1.0);
    }
    return cost * cells;
}

// Runs `passes` on grid g into the block at `offset`: one pass per direction with every light in
// it (coherent), or one pass per light sweep, on `device`. Counts what ran into `report`.
void runPasses(const PassSweeps& passes, const SweepGrid& g, size_t offset, bool coherent, const KernelInputs& inputs,
               PropagationPasses& device, IlluminationVolume& volume, LightUpdate& report) {
    PropagationPass pass;
    pass.march = &inputs.params;
    pass.noise = &inputs.noise;
    pass.sigma = g.sigma;
    pass.sigma_generation = g.sigma_generation;
    pass.offset = offset;
    for (const auto& sweeps : passes) {
        if (sweeps.empty()) continue;
        const int slices = g.dims[sweeps.front().axis];
        if (coherent) {
            pass.sweeps = mergeSharedGeometry(sweeps);
            report.sweeps += int(pass.sweeps.size());
            device.propagate(pass, volume);
            report.passes += 1;
            report.slices += slices;
            continue;
        }
        report.sweeps += int(sweeps.size());
        for (const kernel::VxPropParams& Q : sweeps) {
            pass.sweeps = {Q};
            device.propagate(pass, volume);
            report.passes += 1;
            report.slices += slices;
        }
    }
}

// The eye sweep (Ropinski Sec. 4.1): the indirect light flows towards the camera along the axis
// facing it. It reads `before`, the light sweeps' indirect block (one light group's, from float
// `first` of the volume), and replaces it.
void sweepTowardsEye(const Indirect& in, const KernelInputs& inputs, const SweepGrid& coarse, glm::vec3 eye_position,
                     const std::vector<float>& before, size_t first, PropagationPasses& device, IlluminationVolume& volume) {
    const glm::vec3 cam = glm::vec3(coarse.world_to_grid * glm::vec4(eye_position, 1.0f));
    const Sweep s = sweepsFor(cam - 0.5f * glm::vec3(coarse.dims), false)[0];
    const float tan_half = std::tan(glm::radians(0.5f * in.angle));
    kernel::VxPropParams Q = baseParams(coarse, 3, blurTaps(in), tan_half, glm::vec3(1.0f));
    // The camera must be beyond the face the sweep leaves through.
    glm::vec3 source = cam;
    if (s.sign > 0) source[s.axis] = std::max(source[s.axis], float(coarse.dims[s.axis]));
    else source[s.axis] = std::min(source[s.axis], 0.0f);
    Q.axis = s.axis;
    Q.direction = s.sign;
    Q.source = source;
    Q.source_is_position = 1;
    Q.flow = -1.0f;
    Q.eye_sweep = 1;
    PropagationPass pass;
    pass.sweeps = {Q};
    pass.march = &inputs.params;
    pass.noise = &inputs.noise;
    pass.sigma = coarse.sigma;
    pass.sigma_generation = coarse.sigma_generation;
    pass.offset = first;
    pass.input = &before;
    device.propagate(pass, volume);
}

// The brightest radiance a light brings into the grid (luminance): what its sweeps add at most,
// and so what adding and later subtracting it can leave behind as float residue.
double peakRadiance(const kernel::VxLight& light, const SweepGrid& g) {
    const double y = luminance(light.color);
    if (light.type == VX_LIGHT_DIRECTIONAL) return y;
    const glm::vec3 at = glm::vec3(g.world_to_grid * glm::vec4(light.position, 1.0f));
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

StageActivity propagationActivity(const Scene& s, const std::string& what) {
    if (s.render.method == RenderMethod::Reference)
        return {false, kReferenceComputesAllLight};
    if (s.effects.shadows != ShadowMethod::Propagation || (enabledLightCount(s, false) == 0 && !emissionLightsTheMedium(s))) {
        std::string why = "skipped: no effect in the scene needs an illumination volume";
        if (s.effects.shadows == ShadowMethod::Propagation) why += " (propagation shadows but no light or lit emission to propagate)";
        else if (s.effects.indirect) why += " (indirect light needs effects.shadows = propagation)";
        return {false, why};
    }
    return {true, what};
}

// Distinct across every stage in the process, like the SAT's generations.
uint64_t nextGridGeneration() {
    static std::atomic<uint64_t> next{1};
    return next++;
}

// Hands the march volume `v` (the propagation's or the eye pass's) under `scene`: its block, and
// the share of the sky a multiply scattering medium keeps at its surface (the march scatters the
// sky unoccluded; the reference traces it itself).
void lightTheMarchFrom(const IlluminationVolume& v, const Scene& scene, MarchLighting& lighting) {
    if (scene.effects.shadows != ShadowMethod::Propagation) return;
    const auto& indirect = scene.effects.indirect;
    if (indirect && indirect->model == IndirectModel::Diffusion && scene.render.method == RenderMethod::March)
        lighting.ambient_scale = diffuseSkyFactor(scene.volume().material.albedo, scene.volume().material.anisotropy);
    if (v.values.empty()) return;
    kernel::VxPropagationMarch& b = lighting.blocks.propagation;
    b.world_to_illum = v.world_to_illum;
    b.illum_dims = v.dims;
    b.chroma_factor = v.chroma;
    b.chroma_dims = v.chroma_dims;
    b.indirect_offset = int(v.indirectOffset());
    b.block_floats = int(v.blockFloats());
    b.indirect_weight = indirect ? indirect->strength / (4.0f * float(M_PI)) : 0.0f;
    b.light_filter = scene.effects.propagation.filter == Filter::Tricubic ? VX_FILTER_TRICUBIC : VX_FILTER_TRILINEAR;
    lighting.setArray("Illumination", v.values.data(), v.values.size() * sizeof(float));
}

}  // namespace

bool illuminationVolumeRuns(const Scene& scene) { return propagationActivity(scene, "").runs; }

size_t illuminationBytes(glm::ivec3 d, bool indirect, int chroma, bool emission, bool transport, bool scattering, int blocks) {
    const size_t cells = size_t(d.x) * d.y * d.z;
    // The light grid, its mask, the direct RGB, and an x pass's slice-major copies of the
    // extinction and of its RGB result (CPU).
    size_t bytes = cells * (sizeof(float) + 1 + 3 * sizeof(float) + 4 * sizeof(float));
    if (indirect) {
        const glm::ivec3 c = coarserDims(d, chroma);
        const size_t cc = size_t(c.x) * c.y * c.z;
        // With the eye pass's own volume and its input copy of the indirect cells, reserved whenever
        // indirect light is on, so that toggling the eye pass never changes the grid. The CPU
        // passes keep their x-pass copies between runs (CpuSweepScratch): the propagation's of the
        // coarse extinction when chroma subsampled, and the eye pass's own of the extinction, its
        // input and its result.
        bytes += cc * 3 * sizeof(float) + (chroma > 1 ? 2 * cc * sizeof(float) : 0) + (cells + 2 * cc) * 3 * sizeof(float) +
                 cc * 7 * sizeof(float);
        // The emission grid (and its coarsening), the two orders, the second's source and an x
        // pass's slice-major copy of a source.
        if (emission) bytes += (cells + (chroma > 1 ? cc : 0) + 4 * cc) * 3 * sizeof(float);
        // Of several volumes, the scattering grid (and its coarsening) the emitted light scatters by.
        if (emission && scattering) bytes += (cells + (chroma > 1 ? cc : 0)) * 3 * sizeof(float);
        // Per-material transport: its three planes over the light grid while they are built, and
        // the coarse grid's four planes with an x pass's slice-major copy of them.
        if (transport) bytes += (3 * cells + 8 * cc) * sizeof(float);
    }
    // Each block past the first (a light group's, of a link set): its direct RGB and its share of an
    // x pass's result, and with indirect light its indirect RGB, the eye pass's copy of its volume
    // and its share of a coarse x pass's result.
    if (blocks > 1) {
        const glm::ivec3 c = coarserDims(d, chroma);
        const size_t cc = size_t(c.x) * c.y * c.z;
        bytes += size_t(blocks - 1) * (6 * cells + (indirect ? 3 * cells + 9 * cc : 0)) * sizeof(float);
    }
    return bytes;
}

StageReads IlluminationGridStage::reads() const {
    return {withPlacementKeys({"/volumes/*/material", "/effects/light_resolution", "/effects/light_memory_mb", "/effects/indirect?",
                               "/effects/propagation/chroma_subsampling", "/volumes/*/emission", "/input/light_groups/marches",
                               "/input/light_links/sets", "/input/light_links/shadows"})};
}

StageActivity IlluminationGridStage::activity(const Scene& s) const {
    const bool chroma = s.effects.indirect && s.effects.propagation.chroma_subsampling;
    const bool transport = s.effects.indirect && regionsCarryTransport(s.volume().material.transfer_2d);
    return propagationActivity(s, std::string("the light grid as the sweeps' grid") +
                                      (emissionLightsTheMedium(s) ? ", with the emission box-filtered into its cells" : "") +
                                      (chroma ? ", and its 2x coarsening" : "") +
                                      (transport ? ", with each region's transport depth for the indirect light" : ""));
}

void IlluminationGridStage::release() {
    own_grid_ = LightGrid{};
    emission_.clear();
    scattering_.clear();
    chroma_sigma_.clear();
    chroma_emission_.clear();
    chroma_scattering_.clear();
    transport_sigma_.clear();
    fine_ = coarse_ = SweepGrid{};
    linked_.clear();
}

void IlluminationGridStage::run(StageRun& run) {
    release();
    generation_ = nextGridGeneration();
    const Scene& scene = run.scene({"/effects/indirect?", "/effects/propagation/chroma_subsampling", "/effects/light_resolution",
                                    "/effects/light_memory_mb", "/volumes/*/material", "/volumes/*/emission", "/volumes/*/transform",
                                    "/input/light_groups/marches", "/input/light_links/sets", "/input/light_links/shadows"});
    const Effects& fx = scene.effects;
    const bool indirect = fx.indirect.has_value();
    const int chroma = indirect && fx.propagation.chroma_subsampling ? 2 : 1;
    const LightLinks links = lightLinks(scene);
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame(), xyz_to_working_());
    const glm::vec3 extent = lightGridExtent(inputs);
    const bool emission = emissionLightsTheMedium(scene);
    const bool transport = indirect && !brick_.atlas().transport.empty();
    const bool scattering = inputs.params.volume_count > 0;
    const int blocks = lightGroupMarches(scene) * std::max<int>(1, int(links.sets.size()));   // the volume's blocks
    const GridCost cost{[&](glm::ivec3 d) { return illuminationBytes(d, indirect, chroma, emission, transport, scattering, blocks); },
                        // The kernels index the volume (3 + 3 floats per cell at most, a volume per
                        // light group) with ints.
                        [&](glm::ivec3 d) { return uint64_t(d.x) * d.y * d.z * 6 * uint64_t(blocks) < uint64_t(INT32_MAX); },
                        "illumination volume"};
    std::string warning;
    const int resolution = fitGridResolution(extent, cappedLightResolution(extent, fx.light_resolution),
                                             size_t(fx.light_memory_mb) << 20, cost, "illumination volume", warning);
    if (!warning.empty()) run.warnings.push_back(warning);
    // The shared light grid, unless this volume's memory lowered the resolution below it; the
    // emitted radiance is this stage's own either way.
    const bool shared = resolution == shared_.resolution();
    if (!shared) {
        own_grid_ = buildLightGrid(inputs, resolution, {true, 0.0f, emission});
        if (own_grid_.clamped_cells) run.warnings.push_back(clampedCellsWarning(own_grid_));
        emission_ = std::move(own_grid_.emission);
        scattering_ = std::move(own_grid_.scattering);
    } else if (emission && inputs.params.emission_sources > 0) {
        LightGrid emitted = buildLightGrid(inputs, resolution, {false, 0.0f, true});
        emission_ = std::move(emitted.emission);
        scattering_ = std::move(emitted.scattering);
    }
    const LightGrid& grid = shared ? shared_.grid() : own_grid_;

    fine_.grid_to_world = inputs.index_to_world * grid.lightToIndex();
    fine_.world_to_grid = glm::inverse(fine_.grid_to_world);
    fine_.dims = grid.dims;
    fine_.cells_per_voxel = 1.0f / grid.cell;
    fine_.sigma = &grid.values;
    fine_.sigma_generation = generation_;
    fine_.emission = emission_.empty() ? nullptr : &emission_;
    fine_.scattering = scattering_.empty() ? nullptr : &scattering_;
    coarse_ = fine_;
    if (chroma > 1) {
        chroma_sigma_ = halveGrid(grid.values.data(), grid.dims, 1);
        // Only the coarse grid's emission (and scattering) is swept: the fine one is let go.
        const auto coarsen = [&](std::vector<float>& fine, std::vector<float>& coarse, const std::vector<float>*& fine_ref,
                                 const std::vector<float>*& coarse_ref) {
            if (!fine_ref) return;
            coarse = halveGrid(fine.data(), grid.dims, 3);
            coarse_ref = &coarse;
            fine_ref = nullptr;
            fine = std::vector<float>();
        };
        coarsen(emission_, chroma_emission_, fine_.emission, coarse_.emission);
        coarsen(scattering_, chroma_scattering_, fine_.scattering, coarse_.scattering);
        coarse_.grid_to_world = fine_.grid_to_world * glm::scale(glm::mat4(1.0f), glm::vec3(float(chroma)));
        coarse_.world_to_grid = glm::inverse(coarse_.grid_to_world);
        coarse_.dims = coarserDims(grid.dims, chroma);
        coarse_.cells_per_voxel = fine_.cells_per_voxel / float(chroma);
        coarse_.sigma = &chroma_sigma_;
        coarse_.sigma_generation = nextGridGeneration();
    }
    // A 2D transfer function's per-material transport colour: the indirect sweeps read each
    // channel's extinction times -ln(transport) after the extinction, on their own grid.
    if (transport) {
        const std::vector<float> depth = buildLightGrid(inputs, resolution, {false, 0.0f, false, true}).transport_depth;
        const size_t fine_cells = size_t(grid.dims.x) * grid.dims.y * grid.dims.z;
        const size_t cells = size_t(coarse_.dims.x) * coarse_.dims.y * coarse_.dims.z;
        resizeInHugePages(transport_sigma_, 4 * cells);
        std::copy_n(coarse_.sigma->data(), cells, transport_sigma_.begin());
        for (size_t c = 0; c < 3; ++c) {
            const float* plane = depth.data() + c * fine_cells;
            float* to = transport_sigma_.data() + (c + 1) * cells;
            if (chroma > 1) {
                const std::vector<float> halved = halveGrid(plane, grid.dims, 1);
                std::copy(halved.begin(), halved.end(), to);
            } else {
                std::copy_n(plane, cells, to);
            }
        }
        chroma_sigma_ = std::vector<float>();   // copied: the planes replace it
        coarse_.sigma = &transport_sigma_;
        coarse_.sigma_generation = nextGridGeneration();
        coarse_.transport_planes = true;
    }
    // Light linking: a link set only some volumes shadow sweeps over their extinction alone (a
    // scene of several volumes takes no 2D transfer function, so there is no transport here).
    linked_.resize(links.sets.size());
    for (size_t link = 0; link < links.sets.size(); ++link) {
        if (!links.sets[link].shadows) continue;
        LinkedGrids& l = linked_[link];
        l.fine_sigma = buildLightGrid(inputs, resolution, {.link = int(link)}).values;
        l.fine = fine_;
        l.fine.sigma = &l.fine_sigma;
        l.fine.sigma_generation = nextGridGeneration();
        l.fine.emission = l.fine.scattering = nullptr;   // the emitted light sweeps the every-volume grid
        l.coarse = coarse_;
        l.coarse.emission = l.coarse.scattering = nullptr;
        if (chroma > 1) {
            l.coarse_sigma = halveGrid(l.fine_sigma.data(), grid.dims, 1);
            l.coarse.sigma = &l.coarse_sigma;
            l.coarse.sigma_generation = nextGridGeneration();
        } else {
            l.coarse.sigma = l.fine.sigma;
            l.coarse.sigma_generation = l.fine.sigma_generation;
        }
    }
}

StageReads PropagationStage::reads() const {
    return {withPlacementKeys({"/lights/*/type", "/lights/*/enabled", "/lights/*/position", "/lights/*/direction", "/lights/*/color",
             "/lights/*/intensity", "/lights/*/cone_angle", "/lights/*/cone_softness", "/effects/propagation/blend_axes",
             "/effects/propagation/chroma_subsampling", "/effects/propagation/coherent", "/effects/indirect",
             "/effects/perturbation", "/volumes/*/material/albedo", "/volumes/*/material/anisotropy", "/render/backend",
             "/input/light_groups/of_light", "/input/light_groups/marches", "/input/light_links"})};
}

StageActivity PropagationStage::activity(const Scene& s) const {
    const Effects& fx = s.effects;
    const int lights = enabledLightCount(s, false);
    std::string out = std::to_string(lights) + (lights == 1 ? " light" : " lights") + " swept along " +
                      (fx.propagation.blend_axes ? "the two closest axes, blended" : "the closest axis") +
                      (lights > 1 ? (fx.propagation.coherent ? ", one pass per direction" : ", one pass per light") : "") +
                      "; direct RGB";
    if (const auto& in = fx.indirect) {
        char blur[160];
        std::snprintf(blur, sizeof blur, ", indirect RGB blurred in a %g deg cone over %d taps, ", double(in->angle), in->samples);
        out += blur;
        if (regionsCarryTransport(s.volume().material.transfer_2d)) {
            out += "each region's transport colour";
        } else if (in->model == IndirectModel::Diffusion) {
            out += "diffusion profile";
        } else {
            std::snprintf(blur, sizeof blur, "transport colour (%g, %g, %g)", double(in->transport_color.x),
                          double(in->transport_color.y), double(in->transport_color.z));
            out += blur;
        }
        if (fx.propagation.chroma_subsampling) out += ", chroma subsampled 2x";
        if (emissionLightsTheMedium(s)) out += "; emission lighting the medium (" + std::to_string(kEmittedLightSweeps) + " source sweeps)";
    }
    if (fx.perturbation) out += ", perturbed";
    return propagationActivity(s, out);
}

void PropagationStage::lightTheMarch(const Scene& scene, MarchLighting& lighting) const { lightTheMarchFrom(volume_, scene, lighting); }

void PropagationStage::release() {
    volume_ = IlluminationVolume{};
    passes_.release();
    setup_key_.clear();
    applied_.clear();
    drift_ = 0.0;
}

void PropagationStage::run(StageRun& run) {
    const SweepGrid& fine = grid_.fine();
    const SweepGrid& coarse = grid_.coarse();
    const Scene& scene = run.scene({"/lights", "/effects/propagation/blend_axes", "/effects/propagation/chroma_subsampling",
                                    "/effects/propagation/coherent", "/effects/indirect", "/effects/perturbation", "/volumes/*/material",
                                    "/volumes/*/emission", "/volumes/*/transform", "/input/light_groups/of_light",
                                    "/input/light_groups/marches", "/input/light_links"});
    const Effects& fx = scene.effects;
    const bool indirect = fx.indirect.has_value();
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame());
    // A volume per light group and link set (vx_light_block), each light's sweeps adding into its
    // own (VxPropParams::block_first).
    const int link_blocks = std::max<int>(1, inputs.params.link_sets);
    const int blocks = lightGroupMarches(scene) * link_blocks;
    IlluminationVolume layout;
    layout.dims = fine.dims;
    layout.chroma_dims = indirect ? coarse.dims : glm::ivec3(0);
    const size_t block_floats = layout.blockFloats();
    // The sweeps depend on the grid and these knobs; the lights are compared one by one below.
    std::string setup_key = std::to_string(grid_.generation()) + "|" + std::to_string(blocks) + "|" + hashBytes(inputs.params.noise_offset);
    passes_.keepFor(grid_.generation());   // copies the passes keep of another grid go
    for (const char* key : {"/effects/propagation/blend_axes", "/effects/propagation/chroma_subsampling",
                            "/effects/indirect", "/effects/perturbation", "/volumes/*/material/albedo", "/volumes/*/material/anisotropy",
                            "/render/backend"})
        setup_key += "|" + run.scene.keyText(key);
    const bool coherent = fx.propagation.coherent;
    const bool blend = fx.propagation.blend_axes;
    const kernel::VxPropParams direct = baseParams(fine, 1, directTaps(), 0.0f, glm::vec3(1.0f));
    // The indirect sweep attenuates by the profile's rate; its amplitude scales the light it carries.
    FluenceProfile profile;
    kernel::VxPropParams blurred{};
    if (indirect) {
        profile = indirectFluence(*fx.indirect, scene.volume().material);
        blurred = baseParams(coarse, 3, blurTaps(*fx.indirect), std::tan(glm::radians(0.5f * fx.indirect->angle)), profile.attenuation);
        blurred.transport_planes = coarse.transport_planes ? 1 : 0;
    }
    // The sweeps of `lights`, weighted by `sign`, on both blocks, by the grids they sweep over: 0
    // every volume's, 1 + s link set s's own (light linking, IlluminationGridStage::ownShadows).
    using GridSweeps = std::vector<PassSweeps>;
    const int grids = 1 + inputs.params.link_sets;
    const auto fineAt = [&](int at) -> const SweepGrid& { return at == 0 ? fine : grid_.fineOf(at - 1); };
    const auto coarseAt = [&](int at) -> const SweepGrid& { return at == 0 ? coarse : grid_.coarseOf(at - 1); };
    auto sweepsOf = [&](const std::vector<kernel::VxLight>& lights, float sign, GridSweeps& fine_passes, GridSweeps& coarse_passes) {
        fine_passes.resize(size_t(grids));
        coarse_passes.resize(size_t(grids));
        for (kernel::VxLight l : lights) {
            const int block_first = int(size_t(l.group * link_blocks + l.link_set) * block_floats);
            const int at = grid_.ownShadows(l.link_set) ? 1 + l.link_set : 0;
            kernel::VxPropParams fine_base = direct, coarse_base = blurred;
            fine_base.block_first = coarse_base.block_first = block_first;
            addLightSweeps(l, sign, fineAt(at), fine_base, blend, fine_passes[size_t(at)]);
            l.color *= profile.amplitude;
            if (indirect) addLightSweeps(l, sign, coarseAt(at), coarse_base, blend, coarse_passes[size_t(at)]);
        }
    };
    auto estimate = [&](const GridSweeps& f, const GridSweeps& c) {
        double cost = 0.0;
        for (int at = 0; at < grids; ++at)
            cost += passesCost(f[size_t(at)], fineAt(at), coherent) + passesCost(c[size_t(at)], coarseAt(at), coherent);
        return cost;
    };
    // Runs them on both blocks.
    auto run_sweeps = [&](const GridSweeps& f, const GridSweeps& c, LightUpdate& report) {
        for (int at = 0; at < grids; ++at) {
            runPasses(f[size_t(at)], fineAt(at), 0, coherent, inputs, passes_.on(run.backend), volume_, report);
            if (indirect)
                runPasses(c[size_t(at)], coarseAt(at), volume_.indirectOffset(), coherent, inputs, passes_.on(run.backend), volume_, report);
        }
    };
    auto peak = [&](const std::vector<kernel::VxLight>& lights) {
        double sum = 0.0;
        for (const auto& l : lights) sum += peakRadiance(l, fine);
        return sum;
    };

    LightUpdate report;
    report.lights = int(inputs.lights.size());
    GridSweeps all_fine, all_coarse;
    sweepsOf(inputs.lights, 1.0f, all_fine, all_coarse);
    report.entire_cost = estimate(all_fine, all_coarse) + (indirect ? emittedLightCost(coarse) : 0.0);
    bool selective = false;
    GridSweeps sel_fine, sel_coarse;
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
        run.reused.push_back("light sweeps");
    } else {
        setup_key_.clear();  // stays cleared if a pass throws: the volume is then half updated
        if (selective) {
            report.mode = LightUpdate::Mode::Selective;
            report.lights_out = int(removed.size());
            report.lights_in = int(added.size());
            run_sweeps(sel_fine, sel_coarse, report);
            drift_ += peak(removed) + peak(added);
        } else {
            volume_.dims = fine.dims;
            volume_.chroma = indirect && fx.propagation.chroma_subsampling ? 2 : 1;
            volume_.chroma_dims = indirect ? coarse.dims : glm::ivec3(0);
            volume_.world_to_illum = fine.world_to_grid;
            volume_.blocks = blocks;
            assignInHugePages(volume_.values, size_t(blocks) * volume_.blockFloats(), 0.0f);
            report.mode = LightUpdate::Mode::Entire;
            report.lights_in = int(inputs.lights.size());
            run_sweeps(all_fine, all_coarse, report);
            if (indirect) {
                // The emitted light's volume is the last group's (with light groups, the emitted
                // light's own), of its first link set.
                addEmittedLight(coarse, scene.volume().material, blurred, inputs, passes_.on(run.backend),
                                size_t(blocks - link_blocks) * block_floats, volume_, report);
            }
            drift_ = 0.0;
        }
        applied_ = inputs.lights;
        setup_key_ = setup_key;
    }
    last_update_ = report;
}

StageReads EyePassStage::reads() const {
    return {withPlacementKeys({"/effects/indirect", "/effects/perturbation", "/render/backend"})};
}

StageActivity EyePassStage::activity(const Scene& s) const {
    const StageActivity propagation = propagationActivity(s, "");
    if (!propagation.runs) return propagation;
    if (!s.effects.indirect) return {false, "skipped: the eye pass carries indirect light (effects.indirect is off)"};
    if (!s.effects.propagation.eye_pass) return {false, "skipped: effects.propagation.eye_pass is off"};
    return {true, "indirect light swept once more towards the camera"};
}

void EyePassStage::lightTheMarch(const Scene& scene, MarchLighting& lighting) const { lightTheMarchFrom(volume_, scene, lighting); }

void EyePassStage::run(StageRun& run) {
    passes_.keepFor(grid_.generation());   // as the propagation's, above
    const IlluminationVolume& lit = propagation_.volume();
    volume_ = lit;
    const Scene& scene = run.scene({"/effects/indirect", "/effects/perturbation", "/volumes/*/material", "/volumes/*/transform",
                                    "/volumes/*/instances", "/volumes/*/role"});
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame());
    const glm::vec3 eye_position(cameraToWorld(camera_.camera())[3]);
    for (int b = 0; b < lit.blocks; ++b) {   // each light group's (and link set's) indirect light, on its own
        const size_t first = size_t(b) * lit.blockFloats() + lit.indirectOffset();
        const std::vector<float> before(lit.values.begin() + long(first), lit.values.begin() + long(first + 3 * lit.chromaCells()));
        sweepTowardsEye(*scene.effects.indirect, inputs, grid_.coarse(), eye_position, before, first, passes_.on(run.backend), volume_);
    }
}

}  // namespace voxlux
