#include "lighting/extinction_sat/summed_volume.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/huge_pages.h"
#include "lighting/extinction_sat/kernel/cpu_sat_kernel.h"

namespace voxlux {
namespace {

using U96 = kernel::CpuSatKernel::VxU96;
constexpr size_t kColumns = 64;  // columns whose sums the y and z pass keeps at once
__extension__ using U128 = unsigned __int128;

// Cell value -> integer quanta. Scaling by a power of two is exact; rounding is the only
// quantisation. Negative values never reach here (the atlas clamps them), but stay 0 if they do.
uint64_t quantize(float v, double inv_quantum) { return uint64_t(std::nearbyint(std::max(double(v), 0.0) * inv_quantum)); }

// One plane's three word arrays, addressed by entry.
struct Words {
    uint32_t* lo;
    uint32_t* mid;
    uint32_t* hi;
    U96 load(size_t e) const { return {lo[e], mid[e], hi[e]}; }
    void store(size_t e, U96 v) const {
        lo[e] = v.lo;
        mid[e] = v.mid;
        hi[e] = v.hi;
    }
};

}  // namespace

float satQuantum(float max_value) {
    if (!(max_value > 0.0f)) return 1.0f;
    // 2^e > max_value; e >= -60 keeps the quantum a normal float.
    const int e = std::max(std::ilogb(max_value) + 1, -60);
    return std::ldexp(1.0f, e - 63);
}


namespace {

// Sizes `sat` for `grid` (keeping its storage when it fits) and sets the quanta.
void prepareSummedVolume(const LightGrid& g, SummedVolume& s) {
    s.dims = g.dims;
    s.planes = g.planes;
    resizeInHugePages(s.words, s.planeEntries() * size_t(s.planes) * 3);
    const size_t cells = g.cells();
    for (int p = 0; p < g.planes; ++p) {
        const float* v = g.values.data() + p * cells;
        // A SIMD max (std::max_element returns a position, so it runs one cell at a time).
        float max_value = 0.0f;
#pragma omp simd reduction(max : max_value)
        for (size_t i = 0; i < cells; ++i) max_value = std::max(max_value, v[i]);
        s.quantum[p] = satQuantum(max_value);
    }
}

}  // namespace

void quantizeLightGrid(const LightGrid& g, SummedVolume& s) {
    prepareSummedVolume(g, s);
    std::fill(s.words.begin(), s.words.end(), 0u);
    const size_t sx = size_t(g.dims.x) + 1, sy = size_t(g.dims.y) + 1;
    for (int p = 0; p < g.planes; ++p) {
        const float* v = g.values.data() + p * g.cells();
        const double inv_q = 1.0 / double(s.quantum[p]);
        uint32_t* lo = s.word(p, 0);
        uint32_t* mid = s.word(p, 1);
        tbb::parallel_for(0, g.dims.z, [&](int z) {
            for (int y = 0; y < g.dims.y; ++y)
                for (int x = 0; x < g.dims.x; ++x) {
                    const uint64_t n = quantize(v[(size_t(z) * g.dims.y + y) * g.dims.x + x], inv_q);
                    const size_t e = (size_t(z + 1) * sy + (y + 1)) * sx + (x + 1);
                    lo[e] = uint32_t(n);
                    mid[e] = uint32_t(n >> 32);
                }
        });
    }
}

void buildSummedVolume(const LightGrid& g, SummedVolume& s) {
    prepareSummedVolume(g, s);
    const int dx = g.dims.x, dy = g.dims.y, dz = g.dims.z;
    const size_t sx = size_t(dx) + 1, slice = sx * (size_t(dy) + 1);
    for (int p = 0; p < g.planes; ++p) {
        const Words w{s.word(p, 0), s.word(p, 1), s.word(p, 2)};
        const float* v = g.values.data() + p * g.cells();
        const double inv_q = 1.0 / double(s.quantum[p]);
        std::fill(w.lo, w.lo + slice, 0u);  // the z = 0 face
        std::fill(w.mid, w.mid + slice, 0u);
        std::fill(w.hi, w.hi + slice, 0u);
        // Slice z from slice z - 1 (both in cache): S(y) = S'(y) + C(y), C(y) = C(y-1) + R(y), where
        // R is the row's x prefix sum, C the slice's own table and S' the previous slice. Rows are
        // independent in the x scan; the y recurrence runs across x in SIMD.
        for (int z = 1; z <= dz; ++z) {
            const size_t base = size_t(z) * slice;
            tbb::parallel_for(tbb::blocked_range<int>(0, dy + 1, 16), [&](const tbb::blocked_range<int>& rows) {
                std::vector<uint64_t> quanta(static_cast<size_t>(dx));
                for (int y = rows.begin(); y < rows.end(); ++y) {
                    const size_t row = base + size_t(y) * sx;
                    w.store(row, {0u, 0u, 0u});
                    if (y == 0) {  // the y = 0 face
                        std::fill(w.lo + row, w.lo + row + sx, 0u);
                        std::fill(w.mid + row, w.mid + row + sx, 0u);
                        std::fill(w.hi + row, w.hi + row + sx, 0u);
                        continue;
                    }
                    // Quantise the row as one SIMD loop, then the (serial) running sum, held as
                    // one 128-bit integer: an add with carry per cell, where three 32-bit words
                    // chain compares. Its low 96 bits are the same sum modulo 2^96.
                    const float* cells = v + (size_t(z - 1) * dy + size_t(y - 1)) * dx;
                    for (int x = 0; x < dx; ++x) quanta[size_t(x)] = quantize(cells[x], inv_q);
                    U128 sum = 0;
                    for (int x = 0; x < dx; ++x) {
                        sum += quanta[size_t(x)];
                        const size_t e = row + size_t(x) + 1;
                        w.lo[e] = uint32_t(sum);
                        w.mid[e] = uint32_t(uint64_t(sum) >> 32);
                        w.hi[e] = uint32_t(sum >> 64);
                    }
                }
            });
            // Down each column, with C kept for kColumns columns at a time (the partitioner may hand
            // a task more): each cell reads two table entries, R(y) and S'(y), where
            // R(y) + S(y-1) + S'(y) - S'(y-1) reads four.
            tbb::parallel_for(tbb::blocked_range<size_t>(0, sx, kColumns), [&](const tbb::blocked_range<size_t>& cols) {
                kernel::CpuSatKernel k;
                uint32_t c_lo[kColumns], c_mid[kColumns], c_hi[kColumns];
                const Words c{c_lo, c_mid, c_hi};
                for (size_t x0 = cols.begin(); x0 < cols.end(); x0 += kColumns) {
                    const size_t n = std::min(kColumns, cols.end() - x0);
                    for (size_t i = 0; i < n; ++i) c.store(i, {0u, 0u, 0u});
                    for (int y = 1; y <= dy; ++y) {
                        const size_t row = base + size_t(y) * sx + x0, prev = row - slice;
#pragma GCC ivdep  // the rows and the column sums are distinct
                        for (size_t i = 0; i < n; ++i) {
                            const U96 column = k.vx_u96_add(c.load(i), w.load(row + i));
                            c.store(i, column);
                            w.store(row + i, k.vx_u96_add(w.load(prev + i), column));
                        }
                    }
                }
            });
        }
    }
}

}  // namespace voxlux
