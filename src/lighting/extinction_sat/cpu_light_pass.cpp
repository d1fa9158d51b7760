// CPU light passes: AO shells and shadow cones from the SAT (src/lighting/extinction_sat/kernel/vx_sat.h). When every cell of
// a pass uses the same cuboids (AO shells, directional lights) a row of cells along x is
// evaluated per cuboid as one SIMD batch, the eight corner lookups being contiguous loads across
// the row; cones towards point and spot lights differ per cell, and run cell by cell within each
// cuboid so that neighbouring cells' lookups stay neighbours in memory. Both paths
// compute the same integer box sums and the same float weights as the GL backend's per-cell one.
#include "lighting/extinction_sat/cpu_light_pass.h"
#include "lighting/extinction_sat/summed_volume.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "lighting/extinction_sat/kernel/cpu_sat_kernel.h"

namespace voxlux {
namespace {

using kernel::CpuSatKernel;
constexpr int kRow = 16;  // cells per batch: one AVX-512 vector of 32-bit words

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

// acc[i] += weight * SAT box (c + lo, c + hi) for the cells c = (x0 + i, y, z), i < kRow.
// `Clamp` is false when every lane's x range lies inside the grid, so the loads are contiguous.
template <bool Clamp>
void addCuboidRow(CpuSatKernel& k, int plane, float quantum, const CpuSatKernel::VxCuboid& q, glm::ivec3 c,
                  float* __restrict acc) {
    const glm::ivec3 dims(k.S.dims);
    const int ay = glm::clamp(c.y + q.lo.y, 0, dims.y), by = glm::clamp(c.y + q.hi.y, 0, dims.y);
    const int az = glm::clamp(c.z + q.lo.z, 0, dims.z), bz = glm::clamp(c.z + q.hi.z, 0, dims.z);
    if (ay >= by || az >= bz) return;
    // Entries of the four (y, z) corner lines at x = 0; a lane adds its x.
    const int bb = k.vx_sat_entry_index(0, by, bz), ab = k.vx_sat_entry_index(0, ay, bz);
    const int ba = k.vx_sat_entry_index(0, by, az), aa = k.vx_sat_entry_index(0, ay, az);
    const int xa0 = c.x + q.lo.x, xb0 = c.x + q.hi.x;
    const float weight = q.weight;
    // No `omp simd` here: it would privatise the VxU96 temporaries into memory before they are
    // inlined away; the auto-vectoriser, running after inlining, vectorises the plain loop.
    for (int i = 0; i < kRow; ++i) {
        const int xa = Clamp ? glm::clamp(xa0 + i, 0, dims.x) : xa0 + i;
        const int xb = Clamp ? glm::clamp(xb0 + i, 0, dims.x) : xb0 + i;
        const float sum = k.vx_u96_float(k.vx_sat_lines(plane, bb, ab, ba, aa, xa, xb)) * quantum;
        acc[i] += xa < xb ? weight * sum : 0.0f;
    }
}

// Per-cell boxes of one row, clamped to the grid (lo <= hi), as separate arrays for SIMD.
struct RowBoxes {
    std::vector<int> ax, ay, az, bx, by, bz;
    std::vector<float> weight;   // 0 where a cell has no cuboid
    explicit RowBoxes(int n) : ax(n), ay(n), az(n), bx(n), by(n), bz(n), weight(n) {}
};

// acc[i] += weight[i] * SAT box [a_i, b_i) for i < n: a gather per corner word, across lanes.
void addRowBoxes(CpuSatKernel& k, int plane, float quantum, const RowBoxes& r, int n, float* __restrict acc) {
    const int *ax = r.ax.data(), *ay = r.ay.data(), *az = r.az.data();
    const int *bx = r.bx.data(), *by = r.by.data(), *bz = r.bz.data();
    const float* weight = r.weight.data();
    for (int i = 0; i < n; ++i) {
        const int bb = k.vx_sat_entry_index(0, by[i], bz[i]), ab = k.vx_sat_entry_index(0, ay[i], bz[i]);
        const int ba = k.vx_sat_entry_index(0, by[i], az[i]), aa = k.vx_sat_entry_index(0, ay[i], az[i]);
        acc[i] += weight[i] * (k.vx_u96_float(k.vx_sat_lines(plane, bb, ab, ba, aa, ax[i], bx[i])) * quantum);
    }
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
    const float quantum = k.vx_sat_quantum(plane);
    auto store = [&](size_t cell, float tau) { cache.values[cell * size_t(cache.channels) + size_t(channel)] = tau; };

    // Chunks of kRow cells of one row whose cells the march can read (the rest are skipped).
    auto chunkNeeded = [&](size_t row, int x0) {
        bool any = false;
        for (int i = x0; i < std::min(x0 + kRow, d.x); ++i) any |= needed[row + size_t(i)] != 0;
        return any;
    };
    const int chunks = (d.x + kRow - 1) / kRow;
    tbb::parallel_for(tbb::blocked_range2d<int>(0, d.z, 1, 0, d.y, 4), [&](const tbb::blocked_range2d<int>& r) {
        CpuSatKernel kk = k;
        std::vector<float> acc(size_t(chunks) * kRow);
        std::vector<uint8_t> active(static_cast<size_t>(chunks));
        std::vector<CpuSatKernel::VxCone> cones(static_cast<size_t>(d.x));
        std::vector<CpuSatKernel::VxConeWalk> walks(static_cast<size_t>(d.x));
        RowBoxes boxes(d.x);
        const glm::ivec3 dims(d);
        for (int z = r.rows().begin(); z < r.rows().end(); ++z)
            for (int y = r.cols().begin(); y < r.cols().end(); ++y) {
                const size_t row = (size_t(z) * d.y + y) * d.x;
                bool any = false;
                for (int c = 0; c < chunks; ++c) any |= (active[size_t(c)] = chunkNeeded(row, c * kRow));
                if (!any) continue;
                if (stencil.empty()) {  // per-cell cones (point and spot lights), cuboid by cuboid
                    const kernel::VxLight L = kk.vx_light(light);
                    for (int x = 0; x < d.x; ++x) {
                        cones[size_t(x)] = kk.vx_cone_from({x, y, z}, L);
                        acc[size_t(x)] = kk.vx_cone_start({x, y, z}, cones[size_t(x)]);
                        walks[size_t(x)] = kk.vx_cone_walk_begin();
                    }
                    for (int j = 1; j <= kk.S.cone_cuboids; ++j) {
                        // Each cell's cuboid (scalar geometry), then every box sum of the row at once.
                        for (int x = 0; x < d.x; ++x) {
                            CpuSatKernel::VxCuboid q;
                            const bool on = needed[row + size_t(x)] && kk.vx_cone_step(cones[size_t(x)], walks[size_t(x)], q);
                            const glm::ivec3 a = on ? glm::clamp(glm::ivec3(x, y, z) + q.lo, glm::ivec3(0), dims) : glm::ivec3(0);
                            const glm::ivec3 b = on ? glm::max(glm::clamp(glm::ivec3(x, y, z) + q.hi, glm::ivec3(0), dims), a)
                                                    : glm::ivec3(0);
                            boxes.ax[size_t(x)] = a.x, boxes.ay[size_t(x)] = a.y, boxes.az[size_t(x)] = a.z;
                            boxes.bx[size_t(x)] = b.x, boxes.by[size_t(x)] = b.y, boxes.bz[size_t(x)] = b.z;
                            boxes.weight[size_t(x)] = on ? q.weight : 0.0f;
                        }
                        addRowBoxes(kk, plane, quantum, boxes, d.x, acc.data());
                    }
                    for (int x = 0; x < d.x; ++x)
                        if (needed[row + size_t(x)]) store(row + size_t(x), acc[size_t(x)]);
                    continue;
                }
                // Cuboid by cuboid along the whole row: each cuboid's eight corner lines are then
                // read front to back, few enough streams for the hardware prefetcher.
                std::fill(acc.begin(), acc.end(), 0.0f);
                for (const auto& q : stencil)
                    for (int c = 0; c < chunks; ++c) {
                        if (!active[size_t(c)]) continue;
                        const int x0 = c * kRow;
                        float* a = acc.data() + size_t(x0);
                        if (x0 + q.lo.x >= 0 && x0 + kRow - 1 + q.hi.x <= d.x)
                            addCuboidRow<false>(kk, plane, quantum, q, {x0, y, z}, a);
                        else
                            addCuboidRow<true>(kk, plane, quantum, q, {x0, y, z}, a);
                    }
                for (int x = 0; x < d.x; ++x)
                    if (needed[row + size_t(x)]) store(row + size_t(x), acc[size_t(x)]);
            }
    });
}

}  // namespace voxlux
