// The propagation's row batches (vx_propagation.h's vx_prop_row_run and vx_prop_flow_run, run by
// src/lighting/propagation/cpu_propagation.cpp) against the per-cell sweep they stand in for
// (vx_prop_cell), cell by cell, on the CPU alone (tests/lighting/batch_paths.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "lighting/batch_paths.h"
#include "lighting/light_grid.h"
#include "lighting/propagation/cpu_propagation.h"
#include "lighting/propagation/kernel/cpu_propagation_kernel.h"
#include "lighting/propagation/light_sweeps.h"

namespace voxlux::test {
namespace {

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
                            for (int ch = 0; ch < 3; ++ch)
                                per_cell[at + ch] = kernel::vx_radiance_add(
                                    per_cell[at + ch], k.vx_prop_added(k.vx_prop_weight(i, j), ch, value[Q.channels == 1 ? 0 : ch]));
                        }
                    std::swap(prev, cur);
                }
                // Measured at most 1.1e-6 direct, 2.0e-6 for source sweeps (the directional batch
                // sums the trapezoid as weights times samples and the taps as one stencil) and 1e-7
                // for the point light (the same arithmetic, which the compiler fuses differently, and
                // carried from slice to slice). A stale extinction copy would be off by far more.
                const double error = relativeError(batched.values, per_cell);
                std::printf("  sweep, axis %d, sign %+d, %-14s max |batch - per cell| / peak %.2g\n", axis, sign, kind.c_str(), error);
                EXPECT_LE(error, 3e-6) << "axis " << axis << ", sign " << sign << ", " << kind;
            }
}

}  // namespace
}  // namespace voxlux::test
