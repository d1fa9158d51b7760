// The CPU's batch paths against the per-cell kernel they stand in for, on the CPU alone (these
// run under VOXLUX_SKIP_GL=1 and in a VOXLUX_GL=OFF build): the light passes' row batches
// (src/cpu_light_pass.cpp) against vx_ambient_tau and vx_cone_tau cell by cell, and the
// propagation's row batches (src/cpu_propagation.cpp) against vx_prop_cell cell by cell. The GL
// backend runs the per-cell kernel, so this is what ties the backends' arithmetic together where
// no GL is.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "lighting/extinction_sat/kernel/cpu_sat_kernel.h"
#include "lighting/propagation/kernel/cpu_propagation_kernel.h"
#include "lighting/extinction_sat/cpu_light_pass.h"
#include "lighting/propagation/cpu_propagation.h"
#include "lighting/light_grid.h"
#include "lighting/propagation/light_sweeps.h"
#include "lighting/extinction_sat/summed_volume.h"

namespace voxlux::test {
namespace {

std::vector<float> randomValues(size_t n, float peak, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> v(n);
    for (auto& x : v) x = peak * u(rng) * u(rng);   // many thin cells, a few dense ones
    return v;
}

kernel::VxLight directionalLight(glm::vec3 travel) {
    kernel::VxLight l{};
    l.type = VX_LIGHT_DIRECTIONAL;
    l.direction = glm::normalize(travel);
    l.cos_outer = l.cos_inner = 1.0f;
    l.color = glm::vec3(2.0f, 1.5f, 1.0f);
    return l;
}

kernel::VxLight pointLight(glm::vec3 position) {
    kernel::VxLight l{};
    l.type = VX_LIGHT_POINT;
    l.position = position;
    l.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    l.cos_outer = l.cos_inner = 1.0f;
    l.color = glm::vec3(40.0f);
    return l;
}

// Largest |a - b| over the peak of |b|.
double relativeError(const std::vector<float>& a, const std::vector<float>& b) {
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, std::abs(double(a[i]) - double(b[i])));
        peak = std::max(peak, std::abs(double(b[i])));
    }
    return peak > 0.0 ? worst / peak : worst;
}

// Every pass kind (AO from the extinction plane and from a bleeding plane, cones towards a
// directional light, a point light inside the grid and one outside), over cells the march needs
// (about two in three): the batched channel equals the per-cell query to float rounding, and
// cells not needed are left as they were.
TEST(BatchPaths, LightPassRowsMatchThePerCellQueries) {
    LightGrid grid;
    grid.dims = glm::ivec3(37, 29, 23);
    grid.planes = 4;
    grid.values = randomValues(grid.cells() * 4, 3.0f, 7);
    std::mt19937 rng(11);
    grid.needed.resize(grid.cells());
    for (auto& n : grid.needed) n = rng() % 3 != 0;
    SummedVolume sat;
    buildSummedVolume(grid, sat);
    const std::vector<kernel::VxLight> lights = {directionalLight({0.3f, -1.0f, 0.45f}), pointLight({12.3f, 20.7f, 9.1f}),
                                                 pointLight({-20.0f, 14.0f, 40.0f})};
    LightPass pass;
    pass.lights = &lights;
    pass.sat = &sat;
    pass.needed = &grid.needed;
    kernel::VxSatParams& S = pass.params;
    S.light_to_world = glm::mat4(1.0f);
    S.world_to_light = glm::mat4(1.0f);
    S.dims = grid.dims;
    S.planes = sat.planes;
    S.quantum = sat.quantum;
    S.cache_floats = 1;
    S.shells = 5;
    S.shell_radius = 6.0f;
    S.cell_world = 1.0f;
    S.cone_tan = std::tan(glm::radians(4.0f));
    S.cone_cuboids = 12;
    S.cone_growth = 0.15f;
    S.cone_growth_total = std::pow(1.15f, 12.0f);

    struct Case {
        const char* name;
        int light;
        int ao_plane;
    };
    for (const Case& c : {Case{"AO, extinction plane", -1, 0}, Case{"AO, bleeding plane", -1, 2},
                          Case{"cones, directional", 0, 0}, Case{"cones, point inside", 1, 0},
                          Case{"cones, point outside", 2, 0}}) {
        S.light = c.light;
        S.ao_plane = c.ao_plane;
        S.channel = 0;
        LightCache batched;
        batched.channels = 1;
        batched.values.assign(grid.cells(), -1.0f);
        fillLightChannelCpu(pass, batched);

        kernel::CpuSatKernel k;
        k.S = S;
        k.sat = sat.words;
        k.lights = lights;
        std::vector<float> per_cell(grid.cells(), -1.0f);
        for (int z = 0; z < grid.dims.z; ++z)
            for (int y = 0; y < grid.dims.y; ++y)
                for (int x = 0; x < grid.dims.x; ++x) {
                    const size_t cell = (size_t(z) * grid.dims.y + y) * grid.dims.x + x;
                    if (!grid.needed[cell]) continue;
                    per_cell[cell] = c.light < 0 ? k.vx_ambient_tau({x, y, z}, c.ao_plane)
                                                 : k.vx_cone_tau({x, y, z}, lights[size_t(c.light)]);
                }
        size_t untouched = 0, left = 0;
        for (size_t i = 0; i < per_cell.size(); ++i)
            if (!grid.needed[i]) ++untouched, left += batched.values[i] == -1.0f;
        EXPECT_EQ(left, untouched) << c.name;
        // Measured: AO and point-light cones are bit-identical, directional cones 1.8e-7 (the row
        // batches sum the same products in the same order; the compiler fuses some differently).
        const double error = relativeError(batched.values, per_cell);
        std::printf("  light pass, %-22s max |batch - per cell| / peak %.2g\n", c.name, error);
        EXPECT_LE(error, 5e-7) << c.name;
    }
}

// One sweep of a directional light along each axis both ways, direct (one channel, no blur),
// indirect (RGB, blurred, attenuated by a transport colour, or by one per cell: a 2D transfer
// function's materials) and a source sweep (indirect, adding each cell's own source), and of a
// point light inside the grid, direct and indirect (the cells
// near its plane step several cells sideways, or read beyond the slice, and are redone per cell):
// the batched volume equals the per-cell sweep to float rounding.
TEST(BatchPaths, PropagationRowsMatchThePerCellSweep) {
    const glm::ivec3 dims(24, 20, 18);
    const size_t cells = size_t(dims.x) * dims.y * dims.z;
    // Three grids, cycled so that the scratch's two kept copies are both hit and evicted.
    const std::vector<float> sigmas[3] = {randomValues(cells, 0.6f, 3), randomValues(cells, 0.6f, 11),
                                          randomValues(cells, 0.6f, 17)};
    const std::vector<float> sources = randomValues(3 * cells, 2.0f, 5);
    // Per-material transport: the first grid's extinction, then it times a random -ln(transport).
    std::vector<float> planes = sigmas[0];
    const std::vector<float> k = randomValues(3 * cells, 2.0f, 23);
    for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < cells; ++i) planes.push_back(sigmas[0][i] * k[c * cells + i]);
    const glm::mat4 grid_to_world = glm::mat4(glm::mat3(0.7f));
    const kernel::VxParams march{};   // no perturbation
    Indirect blur;
    blur.angle = 40.0f;
    // One scratch for every pass, as a device keeps it: an x pass over a grid it has seen reads
    // the slice-major copy kept of it, one over another grid makes its own.
    CpuSweepScratch scratch;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign : {-1, 1})
            for (const std::string kind : {"direct", "indirect", "transport", "source", "point", "point indirect", "point transport"}) {
                const bool point = kind.rfind("point", 0) == 0;
                const bool transport = kind.find("transport") != std::string::npos;
                const bool indirect = kind == "indirect" || kind == "source" || kind == "point indirect" || transport;
                const bool source = kind == "source";
                const int which = (2 * axis + (sign > 0) + (indirect ? 1 : 0) + (source ? 1 : 0) + (point ? 1 : 0)) % 3;
                const std::vector<float>& sigma = transport ? planes : sigmas[which];
                // A flow mostly along the sweep's axis, oblique enough that reads fall between cells.
                glm::vec3 travel(0.35f, -0.2f, 0.25f);
                travel[axis] = float(sign);
                const std::vector<kernel::VxTap> taps = indirect ? blurTaps(blur) : directTaps();
                kernel::VxPropParams Q{};
                Q.grid_to_world = grid_to_world;
                Q.world_to_grid = glm::inverse(grid_to_world);
                Q.dims = dims;
                Q.channels = indirect ? 3 : 1;
                Q.axis = axis;
                Q.direction = sign;
                Q.tap_count = int(taps.size());
                for (size_t t = 0; t < taps.size(); ++t) Q.taps[t] = taps[t];
                Q.light = directionalLight(glm::mat3(grid_to_world) * travel);
                Q.source = glm::mat3(Q.world_to_grid) * Q.light.direction;
                Q.flow = 1.0f;
                Q.blur_tan = indirect ? std::tan(glm::radians(0.5f * blur.angle)) : 0.0f;
                Q.weight = 0.75f;
                Q.atten = indirect ? glm::vec3(0.2f, 0.5f, 0.9f) : glm::vec3(1.0f);
                Q.cells_per_voxel = 1.0f;
                Q.tint = glm::vec3(1.0f, 0.8f, 0.6f);
                Q.source_sweep = source ? 1 : 0;
                Q.transport_planes = transport ? 1 : 0;
                if (point) {   // as the propagation stage sets a point light's sweep
                    glm::vec3 at(0.4f * float(dims.x) + 0.13f, 0.55f * float(dims.y) + 0.27f, 0.45f * float(dims.z) + 0.31f);
                    at[axis] = float(dims[axis]) * (sign > 0 ? 0.3f : 0.7f);
                    Q.light = pointLight(glm::vec3(grid_to_world * glm::vec4(at, 1.0f)));
                    Q.source = at;
                    Q.source_is_position = 1;
                    Q.per_cell_flow = 1;
                    Q.max_slope = 3 + int(std::ceil(std::sqrt(3.0f) * Q.blur_tan));
                }

                IlluminationVolume batched;
                batched.dims = dims;
                batched.values.assign(3 * cells, 0.0f);
                PropagationPass pass;
                pass.sweeps = {Q};
                pass.march = &march;
                pass.sigma = &sigma;
                pass.sigma_generation = transport ? 4 : uint64_t(which) + 1;
                if (source) pass.input = &sources;
                propagateCpu(pass, batched, scratch);

                kernel::CpuPropagationKernel k;
                k.P = march;
                k.Q = Q;
                k.Q.strides = glm::ivec3(1, dims.x, dims.x * dims.y);
                k.prop_sigma = sigma;
                if (source) k.prop_in = sources;
                const int u = k.vx_axis_u(axis), v = k.vx_axis_v(axis);
                std::vector<float> per_cell(3 * cells, 0.0f);
                std::vector<float> prev(size_t(dims[u] * dims[v] * Q.channels), 0.0f), cur(prev.size());
                for (int step = 0; step < dims[axis]; ++step) {
                    k.Q.slice = sign > 0 ? step : dims[axis] - 1 - step;
                    k.prop_prev = prev;
                    for (int j = 0; j < dims[v]; ++j)
                        for (int i = 0; i < dims[u]; ++i) {
                            const glm::vec3 value = k.vx_prop_cell(i, j);
                            for (int ch = 0; ch < Q.channels; ++ch) cur[(size_t(j) * dims[u] + i) * Q.channels + ch] = value[ch];
                            glm::ivec3 c;
                            c[axis] = k.Q.slice;
                            c[u] = i;
                            c[v] = j;
                            const size_t at = ((size_t(c.z) * dims.y + c.y) * dims.x + c.x) * 3;
                            const glm::vec3 rgb = (Q.channels == 1 ? glm::vec3(value.x) : value) * Q.tint;
                            for (int ch = 0; ch < 3; ++ch) per_cell[at + ch] += k.vx_prop_weight(i, j) * rgb[ch];
                        }
                    std::swap(prev, cur);
                }
                // Measured at most 1.1e-6 direct, 2.0e-6 for source sweeps and 1.5e-7 for the point
                // light: the batches sum the trapezoid as weights times samples, or blend its inner
                // points in another order. A stale extinction copy would be off by far more.
                const double error = relativeError(batched.values, per_cell);
                std::printf("  sweep, axis %d, sign %+d, %-14s max |batch - per cell| / peak %.2g\n", axis, sign, kind.c_str(), error);
                EXPECT_LE(error, 3e-6) << "axis " << axis << ", sign " << sign << ", " << kind;
            }
}

}  // namespace
}  // namespace voxlux::test
