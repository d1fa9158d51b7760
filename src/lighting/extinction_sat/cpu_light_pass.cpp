// CPU light passes: AO shells and shadow cones from the SAT, in rows of cells along x (the row
// batches of src/lighting/extinction_sat/kernel/vx_sat.h: VX_SAT_ROW cells, VX_CONE_ROW for cones). When every cell of a pass uses
// the same cuboids (AO shells, directional lights) the row is evaluated cuboid by cuboid, the
// eight corner lookups being contiguous loads across it; cones towards point and spot lights
// differ per cell, and each row walks its cells' cones together. Both add the same vx_sat_term as
// the GL backend's per-cell queries.
#include "lighting/extinction_sat/cpu_light_pass.h"
#include "lighting/extinction_sat/summed_volume.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "lighting/extinction_sat/kernel/cpu_sat_kernel.h"

namespace voxlux {
namespace {

using kernel::CpuSatKernel;
// A row's cells are the bits of one 32-bit mask (the march needs them, or not).
static_assert(VX_SAT_ROW <= 32 && VX_CONE_ROW <= 32);

// The cuboids every cell of the pass shares, or none when they depend on the cell.
std::vector<CpuSatKernel::VxCuboid> sharedStencil(CpuSatKernel& k, int light) {
    std::vector<CpuSatKernel::VxCuboid> stencil;
    if (light < 0) {
        for (int i = 1; i <= k.S.shells; ++i) stencil.push_back(k.vx_shell_cuboid(i));
        return stencil;
    }
    const kernel::VxLight L = k.vx_light(light);
    if (L.type != VX_LIGHT_DIRECTIONAL) return stencil;
    const CpuSatKernel::VxCone cone = k.vx_cone_from(glm::ivec3(0), L);
    stencil.push_back(k.vx_cone_own_cell(cone));
    CpuSatKernel::VxConeWalk walk = k.vx_cone_walk_begin();
    for (int j = 1; j <= k.S.cone_cuboids; ++j) {
        CpuSatKernel::VxCuboid q;
        if (k.vx_cone_step(cone, walk, q)) stencil.push_back(q);
    }
    return stencil;
}

}  // namespace

void fillLightChannelCpu(const LightPass& pass, LightCache& cache) {
    CpuSatKernel k;
    k.S = pass.params;
    k.sat = pass.sat->words;
    k.lights = *pass.lights;
    const glm::ivec3 d = pass.params.dims;
    const int light = pass.params.light, channel = pass.params.channel;
    const int plane = light < 0 ? pass.params.ao_plane : 0;
    const uint8_t* needed = pass.needed->data();
    const std::vector<CpuSatKernel::VxCuboid> stencil = sharedStencil(k, light);
    // The rows of a grid row: VX_SAT_ROW cells for shared cuboids, VX_CONE_ROW for per-cell cones.
    const int width = stencil.empty() ? VX_CONE_ROW : VX_SAT_ROW;
    const int chunks = (d.x + width - 1) / width;
    tbb::parallel_for(tbb::blocked_range2d<int>(0, d.z, 1, 0, d.y, 4), [&](const tbb::blocked_range2d<int>& r) {
        CpuSatKernel kk = k;
        std::vector<CpuSatKernel::VxSatRow> rows(stencil.empty() ? 0 : size_t(chunks));
        std::vector<CpuSatKernel::VxConeRow> cones(stencil.empty() ? size_t(chunks) : 0);
        std::vector<uint32_t> chunk_needed(static_cast<size_t>(chunks));   // bit i: the march reads cell x0 + i
        for (int z = r.rows().begin(); z < r.rows().end(); ++z)
            for (int y = r.cols().begin(); y < r.cols().end(); ++y) {
                const size_t row = (size_t(z) * d.y + y) * d.x;
                bool any = false;
                for (int c = 0; c < chunks; ++c) {
                    uint32_t bits = 0;
                    for (int i = 0; i < std::min(width, d.x - c * width); ++i) bits |= uint32_t(needed[row + size_t(c * width + i)] != 0) << i;
                    chunk_needed[size_t(c)] = bits;
                    any |= bits != 0;
                }
                if (!any) continue;
                auto store = [&](int c, const float* tau) {
                    for (int i = 0; i < std::min(width, d.x - c * width); ++i)
                        if ((chunk_needed[size_t(c)] >> i) & 1u)
                            cache.values[(row + size_t(c * width + i)) * size_t(cache.channels) + size_t(channel)] = tau[i];
                };
                if (stencil.empty()) {  // per-cell cones (point and spot lights): each stage across the grid row
                    const kernel::VxLight L = kk.vx_light(light);
                    for (int c = 0; c < chunks; ++c)
                        if (chunk_needed[size_t(c)] != 0) kk.vx_cone_row_begin({c * width, y, z}, L, chunk_needed[size_t(c)], cones[size_t(c)]);
                    for (int j = 1; j <= kk.S.cone_cuboids; ++j) {
                        for (int c = 0; c < chunks; ++c)
                            if (chunk_needed[size_t(c)] != 0) kk.vx_cone_row_boxes(cones[size_t(c)]);
                        for (int c = 0; c < chunks; ++c)
                            if (chunk_needed[size_t(c)] != 0) kk.vx_cone_row_add(cones[size_t(c)]);
                    }
                    for (int c = 0; c < chunks; ++c) store(c, cones[size_t(c)].tau);
                    continue;
                }
                // Cuboid by cuboid along the whole grid row: each cuboid's eight corner lines are
                // then read front to back, few enough streams for the hardware prefetcher.
                for (auto& sums : rows) std::fill(std::begin(sums.tau), std::end(sums.tau), 0.0f);
                for (const auto& q : stencil)
                    for (int c = 0; c < chunks; ++c) {
                        if (chunk_needed[size_t(c)] == 0) continue;
                        const int x0 = c * width;
                        // (clamp_x as a constant: each call inlines a loop of its own, the
                        // unclamped one with contiguous loads)
                        if (kk.vx_sat_row_inside(q, x0))
                            kk.vx_sat_add_cuboid_row(plane, q, {x0, y, z}, false, rows[size_t(c)]);
                        else
                            kk.vx_sat_add_cuboid_row(plane, q, {x0, y, z}, true, rows[size_t(c)]);
                    }
                for (int c = 0; c < chunks; ++c) store(c, rows[size_t(c)].tau);
            }
    });
}

}  // namespace voxlux
