#include "light_grid.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "cpu_kernel.h"

namespace voxlux {
namespace {

// One voxel's share of one cell along an axis: the voxel (local index `voxel`, spanning
// [voxel, voxel + 1)) and the length of its overlap with the cell, in voxels.
struct Overlap {
    int voxel;
    double length;
};

// For each cell along an axis of `voxels` voxels cut into cells of `cell` voxels, the voxels it
// overlaps. This is the exact box filter of the voxels' piecewise-constant field.
std::vector<std::vector<Overlap>> axisOverlaps(int cells, int voxels, double cell) {
    std::vector<std::vector<Overlap>> out(static_cast<size_t>(cells));
    for (int i = 0; i < cells; ++i) {
        const double lo = i * cell, hi = std::min((i + 1) * cell, double(voxels));
        for (int v = int(std::floor(lo)); v < int(std::ceil(hi)) && v < voxels; ++v) {
            const double length = std::min(double(v + 1), hi) - std::max(double(v), lo);
            if (length > 0) out[size_t(i)].push_back({v, length});
        }
    }
    return out;
}

// 1 for cells within one cell of a cell with extinction: the trilinear cache lookup of any sample
// the march shades reads only those.
std::vector<uint8_t> neededCells(const LightGrid& g) {
    std::vector<uint8_t> needed(g.cells(), 0);
    const glm::ivec3 d = g.dims;
    tbb::parallel_for(0, d.z, [&](int z) {
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                bool any = false;
                for (int dz = -1; dz <= 1 && !any; ++dz)
                    for (int dy = -1; dy <= 1 && !any; ++dy)
                        for (int dx = -1; dx <= 1 && !any; ++dx) {
                            const int nx = x + dx, ny = y + dy, nz = z + dz;
                            if (nx < 0 || ny < 0 || nz < 0 || nx >= d.x || ny >= d.y || nz >= d.z) continue;
                            any = g.values[(size_t(nz) * d.y + ny) * d.x + nx] > 0.0f;
                        }
                needed[(size_t(z) * d.y + y) * d.x + x] = any;
            }
    });
    return needed;
}

}  // namespace

glm::mat4 LightGrid::lightToIndex() const {
    glm::mat4 m(cell);
    m[3] = glm::vec4(origin, 1.0f);
    return m;
}

size_t lightGridBytes(glm::ivec3 d, int planes, int cache_channels) {
    const size_t cells = size_t(d.x) * d.y * d.z;
    const size_t sat_entries = size_t(d.x + 1) * (d.y + 1) * (d.z + 1);
    return cells * (planes * sizeof(float) + 1 + cache_channels * sizeof(float)) + sat_entries * planes * 12;
}

glm::ivec3 lightGridDims(glm::vec3 extent, int resolution) {
    const float cell = std::max({extent.x, extent.y, extent.z}) / float(resolution);
    return glm::max(glm::ivec3(glm::ceil(extent / cell - 1e-4f)), glm::ivec3(1));
}

int fitLightResolution(glm::vec3 extent, int requested, int planes, int cache_channels, size_t budget,
                       std::string& warning) {
    int r = requested;
    while (r > 2 && lightGridBytes(lightGridDims(extent, r), planes, cache_channels) > budget) --r;
    if (r != requested) {
        const size_t need = lightGridBytes(lightGridDims(extent, requested), planes, cache_channels);
        warning = "light grid of " + std::to_string(requested) + " cells needs " + std::to_string(need >> 20) +
                  " MiB, over effects.light_memory_mb = " + std::to_string(budget >> 20) + "; using " +
                  std::to_string(r) + " cells instead";
    }
    return r;
}

LightGrid buildLightGrid(const KernelInputs& in, int resolution, float bleeding) {
    kernel::CpuKernel k = bindCpuKernel(in);
    const glm::ivec3 bmin = in.pages->bricks_min, bmax = in.pages->bricks_max;
    const glm::ivec3 voxels = (bmax - bmin + 1) * VX_BRICK;
    LightGrid g;
    g.planes = bleeding > 0.0f ? 4 : 1;
    g.dims = lightGridDims(glm::vec3(voxels), resolution);
    g.cell = float(std::max({voxels.x, voxels.y, voxels.z})) / float(resolution);
    // Voxel v's value holds on [v - 1/2, v + 1/2): the grid starts half a voxel below the first.
    g.origin = glm::vec3(bmin * VX_BRICK) - 0.5f;
    g.values.assign(g.cells() * g.planes, 0.0f);
    auto ox = axisOverlaps(g.dims.x, voxels.x, g.cell);
    auto oy = axisOverlaps(g.dims.y, voxels.y, g.cell);
    auto oz = axisOverlaps(g.dims.z, voxels.z, g.cell);
    const double inv_volume = 1.0 / (double(g.cell) * g.cell * g.cell);
    const size_t plane = g.cells();

    tbb::parallel_for(0, g.dims.z, [&](int cz) {
        for (int cy = 0; cy < g.dims.y; ++cy)
            for (int cx = 0; cx < g.dims.x; ++cx) {
                double sum[4] = {0, 0, 0, 0};
                for (const Overlap& z : oz[size_t(cz)])
                    for (const Overlap& y : oy[size_t(cy)]) {
                        glm::ivec3 last_brick(INT32_MIN);
                        int slot = VX_PAGE_EMPTY;
                        for (const Overlap& x : ox[size_t(cx)]) {
                            const glm::ivec3 local(x.voxel, y.voxel, z.voxel);
                            const glm::ivec3 brick = bmin + local / VX_BRICK;
                            if (brick != last_brick) {
                                slot = k.vx_page_lookup(brick);
                                last_brick = brick;
                            }
                            if (slot == VX_PAGE_EMPTY) continue;
                            const glm::ivec3 o = local % VX_BRICK;
                            kernel::CpuKernel::VxCorners c{
                                slot * VX_BRICK_VOXELS + (o.z * VX_BRICK_STRIDE + o.y) * VX_BRICK_STRIDE + o.x, 0, 0, 0};
                            const float sigma = k.vx_value_extinction(k.vx_atlas_density(c.base));
                            if (sigma <= 0.0f) continue;
                            const double w = x.length * y.length * z.length * sigma;
                            sum[0] += w;
                            if (g.planes == 1) continue;
                            const glm::vec3 a = k.vx_albedo(c);
                            for (int ch = 0; ch < 3; ++ch) sum[ch + 1] += w * (1.0 - double(bleeding) * a[ch]);
                        }
                    }
                const size_t i = (size_t(cz) * g.dims.y + cy) * g.dims.x + cx;
                for (int p = 0; p < g.planes; ++p) g.values[p * plane + i] = float(sum[p] * inv_volume);
            }
    });
    g.needed = neededCells(g);
    return g;
}

}  // namespace voxlux
