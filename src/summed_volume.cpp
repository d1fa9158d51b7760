#include "summed_volume.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "cpu_kernel.h"

namespace voxlux {
namespace {

using U96 = kernel::CpuKernel::VxU96;

// One plane's three word arrays, addressed by entry.
struct Words {
    uint32_t *lo, *mid, *hi;
    U96 load(size_t e) const { return {lo[e], mid[e], hi[e]}; }
    void store(size_t e, U96 v) const {
        lo[e] = v.lo;
        mid[e] = v.mid;
        hi[e] = v.hi;
    }
};

// Entries [dst, dst + count) += entries [src, src + count), with the kernel's modular addition.
void addRange(const Words& w, size_t dst, size_t src, size_t count) {
    kernel::CpuKernel k;
    VX_SIMD_LOOP
    for (size_t i = 0; i < count; ++i) w.store(dst + i, k.vx_u96_add(w.load(dst + i), w.load(src + i)));
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
        uint32_t* lo = s.word(p, 0);
        uint32_t* mid = s.word(p, 1);
        tbb::parallel_for(0, g.dims.z, [&](int z) {
            for (int y = 0; y < g.dims.y; ++y)
                for (int x = 0; x < g.dims.x; ++x) {
                    // v / q scales by a power of two: exact; rounding is the only quantisation.
                    const double units = std::nearbyint(std::max(double(v[(size_t(z) * g.dims.y + y) * g.dims.x + x]), 0.0) / q);
                    const auto n = uint64_t(units);
                    const size_t e = (size_t(z + 1) * sy + (y + 1)) * sx + (x + 1);
                    lo[e] = uint32_t(n);
                    mid[e] = uint32_t(n >> 32);
                }
        });
    }
    return s;
}

void scanSummedVolume(SummedVolume& s) {
    const size_t sx = size_t(s.dims.x) + 1, sy = size_t(s.dims.y) + 1, sz = size_t(s.dims.z) + 1;
    for (int p = 0; p < s.planes; ++p) {
        const Words w{s.word(p, 0), s.word(p, 1), s.word(p, 2)};
        // x and y run within a z slice (which stays in cache); z adds whole slices in turn.
        tbb::parallel_for(size_t(1), sz, [&](size_t z) {
            kernel::CpuKernel k;
            const size_t slice = z * sy * sx;
            for (size_t y = 1; y < sy; ++y) {
                const size_t row = slice + y * sx;
                U96 run = w.load(row);
                for (size_t x = 1; x < sx; ++x) {
                    run = k.vx_u96_add(run, w.load(row + x));
                    w.store(row + x, run);
                }
                if (y > 1) addRange(w, row, row - sx, sx);
            }
        });
        for (size_t z = 2; z < sz; ++z)
            tbb::parallel_for(tbb::blocked_range<size_t>(0, sy * sx, 8192), [&](const tbb::blocked_range<size_t>& r) {
                addRange(w, z * sy * sx + r.begin(), (z - 1) * sy * sx + r.begin(), r.size());
            });
    }
}

}  // namespace voxlux
