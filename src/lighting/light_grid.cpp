#include "lighting/light_grid.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <tuple>

#include <tbb/parallel_for.h>

#include "core/huge_pages.h"
#include "kernel/cpu_kernel_data.h"

namespace voxlux {
namespace {

// The cells along an axis of `voxels` voxels cut into cells of `cell` voxels: cell i spans
// [i * cell, min((i + 1) * cell, voxels)). The box filter weights a voxel [v, v + 1) by its overlap
// with a cell, so it is exact for the voxels' piecewise-constant field.
struct AxisCells {
    int cells;
    int voxels;
    double cell;

    double lo(int i) const { return i * cell; }
    double hi(int i) const { return std::min((i + 1) * cell, double(voxels)); }
    // Length of voxel v's overlap with cell i (0 or less: none).
    double overlap(int i, int v) const { return std::min(double(v + 1), hi(i)) - std::max(double(v), lo(i)); }
    // Calls f(cell, overlap length) for every cell voxel v overlaps. The search starts one cell
    // early, so a quotient v / cell rounded up cannot skip a cell.
    template <class F>
    void eachCellOf(int v, F&& f) const {
        for (int i = std::max(int(std::floor(v / cell)) - 1, 0); i < cells && lo(i) < v + 1; ++i)
            if (const double length = overlap(i, v); length > 0) f(i, length);
    }
};

// An occupied brick: its coordinate relative to the occupied box's lowest brick, and its slot.
struct OccupiedBrick {
    glm::ivec3 local;
    int slot;
};

// The page table's bricks in the medium's box (PageTable::medium_min) in (z, y, x) order, so every
// cell sums its voxels in one fixed order.
std::vector<OccupiedBrick> occupiedBricks(const PageTable& pages) {
    std::vector<OccupiedBrick> out;
    out.reserve(pages.occupied);
    for (int i = 0; i < pages.brick_capacity; ++i) {
        const glm::ivec4& e = pages.entries[size_t(i)];
        if (e.w != VX_PAGE_EMPTY && glm::all(glm::greaterThanEqual(glm::ivec3(e), pages.medium_min)) &&
            glm::all(glm::lessThanEqual(glm::ivec3(e), pages.medium_max)))
            out.push_back({glm::ivec3(e) - pages.medium_min, e.w});
    }
    std::sort(out.begin(), out.end(), [](const OccupiedBrick& a, const OccupiedBrick& b) {
        return std::tie(a.local.z, a.local.y, a.local.x) < std::tie(b.local.z, b.local.y, b.local.x);
    });
    return out;
}

// 1 for cells within one cell of a cell with extinction: the trilinear cache lookup of any sample
// the march shades reads only those. The 3x3x3 dilation runs as three one-axis passes, row by row
// (a row's neighbours along y and z are whole rows one row or one slice away).
std::vector<uint8_t> neededCells(const LightGrid& g) {
    const glm::ivec3 d = g.dims;
    const size_t row = size_t(d.x), slice = size_t(d.x) * d.y;
    std::vector<uint8_t> a(g.cells()), b(g.cells());
    const auto eachRow = [&](auto&& f) {
        tbb::parallel_for(0, d.z, [&](int z) {
            for (int y = 0; y < d.y; ++y) f(y, z, (size_t(z) * d.y + y) * row);
        });
    };
    eachRow([&](int, int, size_t r) {
        for (size_t x = 0; x < row; ++x) a[r + x] = g.values[r + x] > 0.0f;
    });
    eachRow([&](int, int, size_t r) {
        const uint8_t* in = &a[r];
        for (size_t x = 0; x < row; ++x) b[r + x] = in[x] | (x > 0 ? in[x - 1] : 0) | (x + 1 < row ? in[x + 1] : 0);
    });
    // Along y (from b into a), then z (from a into b): the rows before and after, where there are.
    for (int axis = 1; axis < 3; ++axis) {
        const std::vector<uint8_t>& from = axis == 1 ? b : a;
        std::vector<uint8_t>& to = axis == 1 ? a : b;
        const size_t step = axis == 1 ? row : slice;
        eachRow([&](int y, int z, size_t r) {
            const int at = axis == 1 ? y : z;
            const bool before = at > 0, after = at + 1 < d[axis];
            for (size_t x = 0; x < row; ++x)
                to[r + x] = from[r + x] | (before ? from[r - step + x] : 0) | (after ? from[r + step + x] : 0);
        });
    }
    return b;
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

glm::vec3 occupiedExtent(const PageTable& pages) { return glm::vec3((pages.medium_max - pages.medium_min + 1) * VX_BRICK); }

glm::vec3 lightGridExtent(const KernelInputs& in) {
    if (in.params.volume_count == 0) return occupiedExtent(*in.pages);
    return glm::vec3((in.params.bricks_max - in.params.bricks_min + 1) * VX_BRICK);
}

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
    return fitGridResolution(extent, requested, budget, cost, "light cache", warning);
}

namespace {

// The mean emitted radiance over the voxel at index-space `voxel`, by the 2^3-point midpoint rule
// over the trilinear reconstruction the march samples (a point below the voxel's brick reads the
// brick it lies in, as the march does). Emission is a convex function of the grid value (a
// blackbody's visible radiance grows many times faster than its temperature), so the emission
// of the voxel's own value overstates the mean (Jensen's inequality): 1.5x in the Blender fire of
// docs/accuracy.md.
glm::vec3 meanEmission(kernel::CpuKernelData& k, glm::ivec3 voxel) {
    glm::vec3 sum(0.0f);
    for (int q = 0; q < 8; ++q) {
        const glm::vec3 p = glm::vec3(voxel) + glm::vec3(q & 1 ? 0.25f : -0.25f, q & 2 ? 0.25f : -0.25f, q & 4 ? 0.25f : -0.25f);
        const glm::ivec3 brick = glm::ivec3(glm::floor(p / float(VX_BRICK)));
        const int slot = k.vx_page_lookup(brick);
        if (slot != VX_PAGE_EMPTY) sum = kernel::vx_radiance_add(sum, k.vx_emission(k.vx_single_tap(k.vx_corners_at(slot, brick, p))));
    }
    return sum * 0.125f;
}

}  // namespace

namespace {

// Several volumes (shaders/vx_volumes.h): the grid over the shared frame's box of them all, each
// cell's mean by the midpoint rule over 2^3 points of the cell (1 where cells are no larger than
// the finest voxel), each point the volumes' summed medium through their own reconstruction. So
// every volume is resampled by its own filter, whatever its voxel size or rotation, and the grid
// need not align with any of them. The emission's mean is taken over the same points (the one
// volume's over 2^3 points of each voxel). Cells outside every volume's box cost one box test per
// volume.
LightGrid buildVolumesLightGrid(const KernelInputs& in, int resolution, LightGridContents contents) {
    kernel::CpuKernelData k = bindKernelData(in);
    const float bleeding = contents.bleeding;
    const glm::ivec3 voxels = (k.P.bricks_max - k.P.bricks_min + 1) * VX_BRICK;
    LightGrid g;
    g.planes = !contents.extinction ? 0 : bleeding > 0.0f ? 4 : 1;
    g.dims = lightGridDims(glm::vec3(voxels), resolution);
    g.cell = float(std::max({voxels.x, voxels.y, voxels.z})) / float(resolution);
    g.origin = glm::vec3(k.P.bricks_min * VX_BRICK);
    assignInHugePages(g.values, g.cells() * g.planes, 0.0f);
    const bool emits = contents.emission && k.P.emission_sources > 0;
    if (emits) g.emission.assign(g.cells() * 3, 0.0f);
    if (emits) g.scattering.assign(g.cells() * 3, 0.0f);
    // Each volume's box in the shared frame.
    std::vector<std::pair<glm::vec3, glm::vec3>> boxes;
    const glm::mat4 world_to_shared = glm::inverse(in.index_to_world);
    for (const kernel::VxVolume& v : in.volumes) {
        const glm::mat4 to_shared = world_to_shared * glm::inverse(v.world_to_index);
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        if (growByPageRange(v.pages, to_shared, lo, hi)) boxes.emplace_back(lo, hi);
    }
    const int n = g.cell > 1.0f ? 2 : 1;
    const bool shading = g.planes == 4 || emits;   // the scattering the bleeding and the emitted light take
    const double max_sigma = double(kMaxCellOpticalDepth) / cellWorldSize(in.index_to_world * g.lightToIndex());
    const size_t plane = g.cells();
    std::atomic<uint64_t> clamped{0};
    tbb::parallel_for(0, g.dims.z, [&](int cz) {
        for (int cy = 0; cy < g.dims.y; ++cy)
            for (int cx = 0; cx < g.dims.x; ++cx) {
                const glm::vec3 lo = g.origin + glm::vec3(cx, cy, cz) * g.cell, hi = lo + g.cell;
                if (std::none_of(boxes.begin(), boxes.end(), [&](const auto& b) {
                        return glm::all(glm::lessThan(lo, b.second)) && glm::all(glm::greaterThan(hi, b.first));
                    }))
                    continue;
                double sum[4] = {0.0, 0.0, 0.0, 0.0};
                glm::dvec3 emitted(0.0), scattering(0.0);
                for (int q = 0; q < n * n * n; ++q) {
                    const glm::vec3 at = lo + (glm::vec3(q % n, q / n % n, q / (n * n)) + 0.5f) * (g.cell / float(n));
                    bool inside = false;
                    const auto m = k.vx_volumes_medium(glm::vec3(in.index_to_world * glm::vec4(at, 1.0f)), shading, 0.0f, contents.link, inside);
                    sum[0] += m.sigma;
                    for (int c = 0; c < 3; ++c) sum[c + 1] += double(m.sigma) - double(bleeding) * m.scattering[c];
                    emitted += glm::dvec3(m.emitted);
                    scattering += glm::dvec3(m.scattering);
                }
                const double points = double(n * n * n), mean = sum[0] / points;
                const double scale = mean > max_sigma ? max_sigma / mean : 1.0;   // as buildLightGrid clamps
                clamped += mean > max_sigma;
                const size_t i = (size_t(cz) * g.dims.y + cy) * g.dims.x + cx;
                for (int p = 0; p < g.planes; ++p) g.values[p * plane + i] = float(sum[p] / points * scale);
                for (int ch = 0; emits && ch < 3; ++ch) {
                    g.emission[i * 3 + ch] = float(std::min(emitted[ch] / points, double(VX_FLOAT_MAX)));
                    g.scattering[i * 3 + ch] = float(scattering[ch] / points * scale);
                }
            }
    });
    g.clamped_cells = clamped;
    if (contents.extinction) g.needed = neededCells(g);
    return g;
}

}  // namespace

LightGrid buildLightGrid(const KernelInputs& in, int resolution, LightGridContents contents) {
    if (in.params.volume_count > 0) return buildVolumesLightGrid(in, resolution, contents);
    kernel::CpuKernelData k = bindKernelData(in);
    const float bleeding = contents.bleeding;
    const glm::ivec3 bmin = in.pages->medium_min, bmax = in.pages->medium_max;
    const glm::ivec3 voxels = (bmax - bmin + 1) * VX_BRICK;
    LightGrid g;
    g.planes = !contents.extinction ? 0 : bleeding > 0.0f ? 4 : 1;
    g.dims = lightGridDims(glm::vec3(voxels), resolution);
    g.cell = float(std::max({voxels.x, voxels.y, voxels.z})) / float(resolution);
    // Voxel v's value holds on [v - 1/2, v + 1/2): the grid starts half a voxel below the first.
    g.origin = glm::vec3(bmin * VX_BRICK) - 0.5f;
    assignInHugePages(g.values, g.cells() * g.planes, 0.0f);
    const bool emits = contents.emission && k.P.emission_sources > 0;
    if (emits) g.emission.assign(g.cells() * 3, 0.0f);
    const float* transport = contents.transport && !in.atlas->transport.empty() ? in.atlas->transport.data() : nullptr;
    if (transport) assignInHugePages(g.transport_depth, g.cells() * 3, 0.0f);
    const AxisCells ax{g.dims.x, voxels.x, g.cell}, ay{g.dims.y, voxels.y, g.cell}, az{g.dims.z, voxels.z, g.cell};
    const double inv_volume = 1.0 / (double(g.cell) * g.cell * g.cell);
    const size_t plane = g.cells();
    const float cell_world = cellWorldSize(in.index_to_world * g.lightToIndex());
    const double max_sigma = double(kMaxCellOpticalDepth) / cell_world;
    std::atomic<uint64_t> clamped{0};

    // Only occupied bricks are visited, so the cost follows the occupied voxels, never the
    // occupied box: two small parts far apart cost what the parts cost. Each layer of cells sums
    // the bricks that reach it, in (z, y, x) order, into sums of its own.
    const std::vector<OccupiedBrick> bricks = occupiedBricks(*in.pages);
    tbb::parallel_for(0, g.dims.z, [&](int cz) {
        const int z0 = int(std::floor(az.lo(cz))), z1 = int(std::ceil(az.hi(cz)));  // voxels [z0, z1)
        const auto byZ = [](const OccupiedBrick& b, int z) { return b.local.z < z; };
        const auto begin = std::lower_bound(bricks.begin(), bricks.end(), z0 / VX_BRICK, byZ);
        const auto end = std::lower_bound(begin, bricks.end(), (z1 - 1) / VX_BRICK + 1, byZ);
        std::vector<double> sums(size_t(g.dims.x) * g.dims.y * g.planes, 0.0);
        std::vector<double> emitted(emits ? size_t(g.dims.x) * g.dims.y * 3 : 0, 0.0);
        // Per cell: extinction times -ln(transport) per channel, and the extinction, which clamps
        // the cell as the extinction plane is clamped.
        std::vector<double> depth(transport ? size_t(g.dims.x) * g.dims.y * 4 : 0, 0.0);
        for (auto b = begin; b != end; ++b) {
            const glm::ivec3 first = b->local * VX_BRICK;
            for (int oz = std::max(z0 - first.z, 0); oz < std::min(z1 - first.z, VX_BRICK); ++oz) {
                const int vz = first.z + oz;
                const double z_length = az.overlap(cz, vz);
                if (z_length <= 0) continue;
                for (int oy = 0; oy < VX_BRICK; ++oy)
                    for (int ox = 0; ox < VX_BRICK; ++ox) {
                        kernel::CpuKernelData::VxCorners c{
                            b->slot * VX_BRICK_VOXELS + (oz * VX_BRICK_STRIDE + oy) * VX_BRICK_STRIDE + ox, 0, 0, 0};
                        const float sigma = k.vx_value_extinction(k.vx_atlas_density(c.base));
                        const glm::vec3 le =
                            emits ? meanEmission(k, (b->local + bmin) * VX_BRICK + glm::ivec3(ox, oy, oz)) : glm::vec3(0.0f);
                        if (sigma <= 0.0f && le == glm::vec3(0.0f)) continue;
                        const glm::vec3 albedo = g.planes < 4 ? glm::vec3(0.0f) : k.vx_albedo(k.vx_single_tap(c));
                        glm::dvec3 sigma_k(0.0);   // extinction times -ln(transport colour)
                        if (transport && sigma > 0.0f)
                            for (int ch = 0; ch < 3; ++ch)
                                sigma_k[ch] = -double(sigma) * std::log(std::max(double(transport[size_t(c.base) * 3 + ch]), 1e-6));
                        ay.eachCellOf(first.y + oy, [&](int cy, double y_length) {
                            ax.eachCellOf(first.x + ox, [&](int cx, double x_length) {
                                const double overlap = x_length * y_length * z_length;
                                const size_t cell = size_t(cy) * g.dims.x + cx;
                                if (emits)
                                    for (int ch = 0; ch < 3; ++ch) emitted[cell * 3 + ch] += overlap * le[ch];
                                if (transport) {
                                    for (int ch = 0; ch < 3; ++ch) depth[cell * 4 + ch] += overlap * sigma_k[ch];
                                    depth[cell * 4 + 3] += overlap * sigma;
                                }
                                if (sigma <= 0.0f || g.planes == 0) return;
                                const double w = overlap * sigma;
                                double* sum = sums.data() + cell * g.planes;
                                sum[0] += w;
                                for (int ch = 1; ch < g.planes; ++ch) sum[ch] += w * (1.0 - double(bleeding) * albedo[ch - 1]);
                            });
                        });
                    }
            }
        }
        for (size_t cell = 0; cell < size_t(g.dims.x) * g.dims.y; ++cell) {
            double* sum = sums.data() + cell * g.planes;
            if (g.planes > 0 && sum[0] * inv_volume > max_sigma) {
                ++clamped;
                for (int p = 1; p < g.planes; ++p) sum[p] *= max_sigma / (sum[0] * inv_volume);
                sum[0] = max_sigma / inv_volume;
            }
            const size_t i = size_t(cz) * g.dims.x * g.dims.y + cell;
            for (int p = 0; p < g.planes; ++p) g.values[p * plane + i] = float(sum[p] * inv_volume);
            if (emits)
                for (int ch = 0; ch < 3; ++ch)
                    g.emission[i * 3 + ch] = float(std::min(emitted[cell * 3 + ch] * inv_volume, double(VX_FLOAT_MAX)));
            if (transport) {
                const double mean_sigma = depth[cell * 4 + 3] * inv_volume;
                const double clamp = mean_sigma > max_sigma ? max_sigma / mean_sigma : 1.0;
                for (int ch = 0; ch < 3; ++ch)
                    g.transport_depth[ch * plane + i] = float(std::min(depth[cell * 4 + ch] * inv_volume * clamp, double(VX_FLOAT_MAX)));
            }
        }
    });
    g.clamped_cells = clamped;
    if (contents.extinction) g.needed = neededCells(g);
    return g;
}

bool uniformAlbedo(const KernelInputs& in) {
    return in.params.use_transfer == 0 && in.params.use_color_grid == 0 && in.params.volume_count == 0;
}

LightGrid withUniformBleeding(const LightGrid& extinction, glm::vec3 albedo, float bleeding) {
    assert(extinction.planes == 1);
    // Every field but the values as they are (a uniform albedo is one volume's, which has no
    // scattering plane); the values in one allocation for all four planes.
    LightGrid g{.dims = extinction.dims, .origin = extinction.origin, .cell = extinction.cell, .planes = 4, .values = {},
                .needed = extinction.needed, .emission = extinction.emission, .scattering = {}, .transport_depth = extinction.transport_depth,
                .clamped_cells = extinction.clamped_cells};
    const size_t plane = g.cells();
    resizeInHugePages(g.values, 4 * plane);
    std::copy(extinction.values.begin(), extinction.values.end(), g.values.begin());
    for (int c = 0; c < 3; ++c) {
        const double weight = 1.0 - double(bleeding) * albedo[c];
        tbb::parallel_for(tbb::blocked_range<size_t>(0, plane, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t i = r.begin(); i < r.end(); ++i) g.values[(c + 1) * plane + i] = float(double(g.values[i]) * weight);
        });
    }
    return g;
}

}  // namespace voxlux
