#include "lighting/light_grid.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/parallel_for.h>

#include "kernel/cpu_kernel.h"

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
// the march shades reads only those. The 3x3x3 dilation runs as three one-axis passes.
std::vector<uint8_t> neededCells(const LightGrid& g) {
    const glm::ivec3 d = g.dims;
    std::vector<uint8_t> a(g.cells()), b(g.cells());
    for (size_t i = 0; i < g.cells(); ++i) a[i] = g.values[i] > 0.0f;
    const size_t stride[3] = {1, size_t(d.x), size_t(d.x) * d.y};
    for (int axis = 0; axis < 3; ++axis) {
        const int n = d[axis];
        const size_t s = stride[axis];
        tbb::parallel_for(tbb::blocked_range<size_t>(0, g.cells(), 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t i = r.begin(); i < r.end(); ++i) {
                const int at = int(i / s % size_t(n));
                b[i] = a[i] | (at > 0 ? a[i - s] : 0) | (at + 1 < n ? a[i + s] : 0);
            }
        });
        std::swap(a, b);
    }
    return a;
}

}  // namespace

glm::mat4 LightGrid::lightToIndex() const {
    glm::mat4 m(cell);
    m[3] = glm::vec4(origin, 1.0f);
    return m;
}

float cellWorldSize(const glm::mat4& light_to_world) {
    return std::cbrt(std::abs(glm::determinant(glm::mat3(light_to_world))));
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

bool lightGridIndexable(glm::ivec3 d, int planes, int cache_channels) {
    const uint64_t sat_words = uint64_t(d.x + 1) * (d.y + 1) * (d.z + 1) * uint64_t(planes) * 3;
    const uint64_t cache_floats = uint64_t(d.x) * d.y * d.z * uint64_t(std::max(cache_channels, 1));
    return sat_words < uint64_t(INT32_MAX) && cache_floats < uint64_t(INT32_MAX);
}

std::string clampedCellsWarning(const LightGrid& g) {
    return std::to_string(g.clamped_cells) + " light-grid cells clamped to an optical depth of " +
           std::to_string(int(kMaxCellOpticalDepth)) + " per cell (extreme extinction in the data)";
}

glm::vec3 occupiedExtent(const PageTable& pages) { return glm::vec3((pages.bricks_max - pages.bricks_min + 1) * VX_BRICK); }

int cappedLightResolution(glm::vec3 extent, int requested) {
    return std::min(requested, 4 * int(std::max({extent.x, extent.y, extent.z})));
}

int fitGridResolution(glm::vec3 extent, int requested, size_t budget, const GridCost& cost, const std::string& what,
                      std::string& warning) {
    auto fits = [&](int r) {
        const glm::ivec3 d = lightGridDims(extent, r);
        return cost.bytes(d) <= budget && cost.indexable(d);
    };
    int r = requested;
    while (r > 2 && !fits(r)) --r;
    if (r != requested && !cost.indexable(lightGridDims(extent, requested))) {
        warning = what + " of " + std::to_string(requested) + " cells is beyond the kernel's 32-bit indices (" +
                  cost.index_limit + " over 2^31 values); using " + std::to_string(r) + " cells instead";
    } else if (r != requested) {
        const size_t need = cost.bytes(lightGridDims(extent, requested));
        warning = what + " of " + std::to_string(requested) + " cells needs " + std::to_string(need >> 20) +
                  " MiB, over effects.light_memory_mb = " + std::to_string(budget >> 20) + "; using " +
                  std::to_string(r) + " cells instead";
    }
    return r;
}

int fitLightResolution(glm::vec3 extent, int requested, int planes, int cache_channels, size_t budget,
                       std::string& warning) {
    GridCost cost{[&](glm::ivec3 d) { return lightGridBytes(d, planes, cache_channels); },
                  [&](glm::ivec3 d) { return lightGridIndexable(d, planes, cache_channels); }, "SAT or light cache"};
    return fitGridResolution(extent, requested, budget, cost, "light grid", warning);
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
    const float cell_world = cellWorldSize(in.atlas->index_to_world * g.lightToIndex());
    const double max_sigma = double(kMaxCellOpticalDepth) / cell_world;
    std::atomic<uint64_t> clamped{0};

    // Atlas slot of every brick in the occupied box: a dense table at brick (not voxel)
    // resolution, 1/512 of the voxels, so the filter does no hash lookups.
    const glm::ivec3 nb = bmax - bmin + 1;
    std::vector<int> slots(size_t(nb.x) * nb.y * nb.z);
    tbb::parallel_for(0, nb.z, [&](int z) {
        for (int y = 0; y < nb.y; ++y)
            for (int x = 0; x < nb.x; ++x)
                slots[(size_t(z) * nb.y + y) * nb.x + x] = k.vx_page_lookup(bmin + glm::ivec3(x, y, z));
    });

    tbb::parallel_for(0, g.dims.z, [&](int cz) {
        for (int cy = 0; cy < g.dims.y; ++cy)
            for (int cx = 0; cx < g.dims.x; ++cx) {
                double sum[4] = {0, 0, 0, 0};
                for (const Overlap& z : oz[size_t(cz)])
                    for (const Overlap& y : oy[size_t(cy)])
                        for (const Overlap& x : ox[size_t(cx)]) {
                            const glm::ivec3 local(x.voxel, y.voxel, z.voxel);
                            const glm::ivec3 b = local / VX_BRICK;
                            const int slot = slots[(size_t(b.z) * nb.y + b.y) * nb.x + b.x];
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
                const size_t i = (size_t(cz) * g.dims.y + cy) * g.dims.x + cx;
                if (sum[0] * inv_volume > max_sigma) {
                    ++clamped;
                    for (int p = 1; p < g.planes; ++p) sum[p] *= max_sigma / (sum[0] * inv_volume);
                    sum[0] = max_sigma / inv_volume;
                }
                for (int p = 0; p < g.planes; ++p) g.values[p * plane + i] = float(sum[p] * inv_volume);
            }
    });
    g.clamped_cells = clamped;
    g.needed = neededCells(g);
    return g;
}

}  // namespace voxlux
