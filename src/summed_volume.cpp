#include "summed_volume.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "cpu_kernel.h"

namespace voxlux {
namespace {

using U96 = kernel::CpuKernel::VxU96;

U96 load(const uint32_t* w) { return {w[0], w[1], w[2]}; }
void store(uint32_t* w, U96 v) {
    w[0] = v.lo;
    w[1] = v.mid;
    w[2] = v.hi;
}

// dst[i] += src[i] for `count` consecutive entries, with the kernel's modular addition.
void addRow(uint32_t* dst, const uint32_t* src, size_t count) {
    kernel::CpuKernel k;
    for (size_t i = 0; i < 3 * count; i += 3) store(dst + i, k.vx_u96_add(load(dst + i), load(src + i)));
}

}  // namespace

float satQuantum(float max_value) {
    if (!(max_value > 0.0f)) return 1.0f;
    // 2^e > max_value; e >= -60 keeps the quantum a normal float.
    const int e = std::max(std::ilogb(max_value) + 1, -60);
    return std::ldexp(1.0f, e - 63);
}

SummedVolume quantizeLightGrid(const LightGrid& g) {
    SummedVolume s;
    s.dims = g.dims;
    s.planes = g.planes;
    s.words.assign(s.planeEntries() * s.planes * 3, 0u);
    const size_t cells = g.cells();
    const size_t sx = size_t(g.dims.x) + 1, sy = size_t(g.dims.y) + 1;
    for (int p = 0; p < g.planes; ++p) {
        const float* v = g.values.data() + p * cells;
        const float q = satQuantum(*std::max_element(v, v + cells));
        s.quantum[p] = q;
        uint32_t* plane = s.words.data() + p * s.planeEntries() * 3;
        tbb::parallel_for(0, g.dims.z, [&](int z) {
            for (int y = 0; y < g.dims.y; ++y)
                for (int x = 0; x < g.dims.x; ++x) {
                    // v / q scales by a power of two: exact; rounding is the only quantisation.
                    const double units = std::nearbyint(std::max(double(v[(size_t(z) * g.dims.y + y) * g.dims.x + x]), 0.0) / q);
                    const auto n = uint64_t(units);
                    uint32_t* w = plane + 3 * ((size_t(z + 1) * sy + (y + 1)) * sx + (x + 1));
                    w[0] = uint32_t(n);
                    w[1] = uint32_t(n >> 32);
                }
        });
    }
    return s;
}

void scanSummedVolume(SummedVolume& s) {
    const size_t sx = size_t(s.dims.x) + 1, sy = size_t(s.dims.y) + 1, sz = size_t(s.dims.z) + 1;
    for (int p = 0; p < s.planes; ++p) {
        uint32_t* plane = s.words.data() + p * s.planeEntries() * 3;
        // x and y run within a z slice; z adds whole slices, each depending on the one before.
        tbb::parallel_for(size_t(1), sz, [&](size_t z) {
            uint32_t* slice = plane + 3 * z * sy * sx;
            kernel::CpuKernel k;
            for (size_t y = 1; y < sy; ++y) {
                uint32_t* row = slice + 3 * y * sx;
                for (size_t x = 1; x < sx; ++x) store(row + 3 * x, k.vx_u96_add(load(row + 3 * x), load(row + 3 * (x - 1))));
            }
            for (size_t y = 2; y < sy; ++y) addRow(slice + 3 * y * sx, slice + 3 * (y - 1) * sx, sx);
        });
        for (size_t z = 2; z < sz; ++z) {
            uint32_t* slice = plane + 3 * z * sy * sx;
            const uint32_t* below = slice - 3 * sy * sx;
            tbb::parallel_for(tbb::blocked_range<size_t>(0, sy * sx, 4096), [&](const tbb::blocked_range<size_t>& r) {
                addRow(slice + 3 * r.begin(), below + 3 * r.begin(), r.size());
            });
        }
    }
}

}  // namespace voxlux
