#include "lighting/propagation/cpu_propagation.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/huge_pages.h"
#include "lighting/propagation/kernel/cpu_propagation_kernel.h"

namespace voxlux {
namespace {

using glm::mix;   // the kernel's filters (VX_BILERP) call it unqualified, as GLSL does

// A sweep reads and writes whole slices. For y and z sweeps a slice is rows of x, contiguous in
// the volume's layout; an x sweep's slice is one float per cache line there, so it runs on copies
// laid out slice by slice (x-major: index (x * nz + z) * ny + y) and the result is added back.
struct SliceMajor {
    glm::ivec3 dims;
    size_t natural(int x, int y, int z) const { return (size_t(z) * dims.y + y) * dims.x + x; }
    size_t sliced(int x, int y, int z) const { return (size_t(x) * dims.z + z) * dims.y + y; }

    // Calls f(natural index, sliced index) for every cell, in tiles of 16 x so that both orders
    // stream: 16 contiguous floats read per row on one side, 16 rows written in step on the other.
    template <class F>
    void forEachCell(F&& f) const {
        tbb::parallel_for(0, dims.z, [&](int z) {
            for (int x0 = 0; x0 < dims.x; x0 += 16)
                for (int y = 0; y < dims.y; ++y)
                    for (int x = x0; x < std::min(x0 + 16, dims.x); ++x) f(natural(x, y, z), sliced(x, y, z));
        });
    }

    // `channels` floats per cell from natural to x-major order, into `out`.
    void toSlices(const float* in, int channels, std::vector<float>& out) const {
        resizeInHugePages(out, size_t(dims.x) * dims.y * dims.z * channels);
        forEachCell([&](size_t n, size_t s) {
            for (int c = 0; c < channels; ++c) out[s * channels + c] = in[n * channels + c];
        });
    }
};

// The slice-major copy of the pass's extinction (each of its planes): the one kept for its grid,
// or made into the slot used least recently.
const std::vector<float>& slicedSigma(const PropagationPass& pass, const SliceMajor& layout, CpuSweepScratch& scratch) {
    CpuSweepScratch::SlicedSigma* slot = nullptr;
    for (auto& s : scratch.sigma)
        if (pass.sigma_generation != 0 && s.generation == pass.sigma_generation && s.values.size() == pass.sigma->size()) slot = &s;
    if (!slot) {
        slot = scratch.sigma[0].last_use <= scratch.sigma[1].last_use ? &scratch.sigma[0] : &scratch.sigma[1];
        slot->generation = 0;   // stays 0 if the copy throws
        const size_t cells = size_t(layout.dims.x) * layout.dims.y * layout.dims.z;
        resizeInHugePages(slot->values, pass.sigma->size());
        for (size_t plane = 0; plane < pass.sigma->size() / cells; ++plane) {
            const float* in = pass.sigma->data() + plane * cells;
            float* sliced = slot->values.data() + plane * cells;
            layout.forEachCell([&](size_t n, size_t s) { sliced[s] = in[n]; });
        }
        slot->generation = pass.sigma_generation;
    }
    slot->last_use = ++scratch.uses;
    return slot->values;
}

// The CPU's batch form of vx_prop_cell for the common case: a directional light (or a source
// sweep along an axis), no perturbation. Every cell then reads the previous slice (and, for the extinction
// along a long step, its own slice) at the same offsets, so a row is a weighted sum of shifted
// slice rows (bilinear blends for the extinction, one stencil for the blur taps): SIMD loops over
// contiguous floats. Cells whose reads leave the
// slice, and every other case, run vx_prop_cell itself. The GL backend runs vx_prop_cell
// everywhere, and the tests hold the two backends together.
class RowBatch {
public:
    RowBatch(kernel::CpuPropagationKernel& k, int nu, int nv) : k_(k), nu_(nu), nv_(nv) {
        const kernel::VxPropParams& Q = k.Q;
        const int axis = Q.axis, u = k.vx_axis_u(axis), v = k.vx_axis_v(axis);
        usable_ = Q.source_is_position == 0 && Q.eye_sweep == 0 && !k.vx_perturbed() && Q.strides[u] == 1;
        if (!usable_) return;
        const glm::vec3 back = k.vx_prop_back(glm::vec3(0.0f));   // the same for every cell
        // The extinction samples of vx_prop_cell's composite trapezoid: at fraction f of the step
        // from p (previous slice) to the cell, a blend of the two slices' bilinear reads.
        const int pieces = k.vx_prop_pieces(back);
        const float step_world = k.vx_prop_step_world(back);
        step_world_ = step_world;
        for (int q = 0; q <= pieces; ++q) {
            const float f = float(q) / float(pieces);
            const float w = (q == 0 || q == pieces ? 0.5f : 1.0f) * step_world / float(pieces);
            sigma_.push_back({read(-back[u] * (1.0f - f), -back[v] * (1.0f - f), w), f});
        }
        const float radius = k.vx_prop_blur_radius(back);
        for (int t = 0; t < Q.tap_count; ++t)
            taps_.push_back(read(-back[u] + radius * Q.taps[t].offset.x, -back[v] + radius * Q.taps[t].offset.y, Q.taps[t].weight));
        // Every cell of the row reads the previous slice at the same offsets, so the taps' bilinear
        // corner weights add into one stencil: 9 taps of 4 corners fall on 9-16 cells for the blur
        // radii of the default cone, one multiply-add per stencil cell instead of a blend per tap.
        for (const Read& r : taps_)
            for (int q = 0; q < 4; ++q) {
                const double wu = q & 1 ? r.ta : 1.0 - r.ta, wv = q & 2 ? r.tb : 1.0 - r.tb;
                addToStencil(r.di + (q & 1), r.dj + (q >> 1), wu * wv * r.w);
            }
        lo_ = 0;
        hi_ = nu;
        for (const Read& r : taps_) narrow(r);
        for (const SigmaRead& r : sigma_) narrow(r.at);
        for (int c = 0; c < 3; ++c) atten_[c] = Q.atten[c];
        planes_ = Q.transport_planes != 0 ? 4 : 1;
    }

    // Cells [first, last) of row j, evaluated into `out` (channels per cell, by i); false when
    // the row's reads leave the slices (or the slice is the first).
    bool row(int j, int prev, float* out, int& first, int& last) const {
        const kernel::VxPropParams& Q = k_.Q;
        if (!usable_ || prev < 0 || prev >= Q.dims[Q.axis] || lo_ >= hi_) return false;
        for (const Read& r : taps_)
            if (!rowInside(j, r)) return false;
        for (const SigmaRead& r : sigma_)
            if (!rowInside(j, r.at)) return false;
        const int channels = Q.channels, axis = Q.axis;
        const size_t sv = size_t(Q.strides[k_.vx_axis_v(axis)]), sa = size_t(Q.strides[axis]);
        const size_t plane_cells = size_t(Q.dims.x) * Q.dims.y * Q.dims.z;
        // tau[0]: the step's optical depth; with per-material transport instead tau[1..3], each
        // channel's (vx_prop_cell's k * tau).
        float tau[4][kMaxRow];
        for (int base = lo_; base < hi_; base += kMaxRow) {
            const int n = std::min(kMaxRow, hi_ - base);
            for (int plane = planes_ > 1 ? 1 : 0; plane < planes_; ++plane) {
                float* depth = tau[plane];
                std::fill(depth, depth + n, 0.0f);
                for (const SigmaRead& r : sigma_) {
                    // Row starts; the offset di (negative at a row's start) goes into the index, so
                    // that no pointer is formed outside the arrays.
                    const float* sigma = k_.prop_sigma.data + size_t(plane) * plane_cells;
                    const float* a0 = sigma + size_t(prev) * sa + size_t(j + r.at.dj) * sv;
                    const float* b0 = sigma + size_t(Q.slice) * sa + size_t(j + r.at.dj) * sv;
                    const float ta = r.at.ta, tb = r.at.tb, f = r.slice, w = r.at.w;
                    const int di = r.at.di;
#pragma omp simd
                    for (int q = 0; q < n; ++q) {
                        const int i = base + q + di;
                        const float in_prev = VX_BILERP(a0[i], a0[i + 1], a0[i + sv], a0[i + sv + 1], ta, tb);
                        const float in_here = VX_BILERP(b0[i], b0[i + 1], b0[i + sv], b0[i + sv + 1], ta, tb);
                        depth[q] += w * glm::mix(in_prev, in_here, f);
                    }
                }
            }
            // The blur taps, as their stencil. A cell reads every channel at the same offsets with
            // the same weights, so on the interleaved slice (channels floats per cell) a run of n
            // cells is one run of n * channels contiguous floats.
            float acc[kMaxRow * 3] = {};
            const int floats = n * channels;
            for (const StencilCell& c : stencil_) {
                const float* p = k_.prop_prev.data + (size_t(j + c.dj) * nu_ + size_t(base + c.di)) * channels;
                const float w = c.w;
#pragma omp simd
                for (int m = 0; m < floats; ++m) acc[m] = kernel::vx_radiance_add(acc[m], w * p[m]);
            }
            for (int c = 0; c < channels; ++c) {
                // The channel's optical depth per cell: its own plane, or tau times the medium's k.
                float kt[kMaxRow];
                const float kc = atten_[c];
                if (planes_ > 1) {
                    std::copy_n(tau[c + 1], n, kt);
                } else {
#pragma omp simd
                    for (int q = 0; q < n; ++q) kt[q] = kc * tau[0][q];
                }
                if (Q.source_sweep == 0) {
#pragma omp simd
                    for (int q = 0; q < n; ++q) out[size_t(base + q) * channels + c] = acc[q * channels + c] * k_.vx_exp(-kt[q]);
                    continue;
                }
                // A source sweep adds the cell's own source over the step, as vx_prop_cell does.
                const float* src = k_.prop_in.data + (size_t(Q.slice) * sa + size_t(j) * sv) * 3 + c;
                const float step = step_world_;
#pragma omp simd
                for (int q = 0; q < n; ++q)
                    out[size_t(base + q) * channels + c] = kernel::vx_radiance_add(
                        acc[q * channels + c] * k_.vx_exp(-kt[q]), src[size_t(base + q) * 3] * (step * k_.vx_exp_integral(kt[q])));
            }
        }
        first = lo_;
        last = hi_;
        return true;
    }

private:
    static constexpr int kMaxRow = 256;
    struct Read {
        int di, dj;       // lower corner relative to the cell
        float ta, tb;     // fractions along u and v
        float w;          // weight
    };
    struct SigmaRead {
        Read at;          // in-slice position; w = trapezoid weight times world step
        float slice;      // 0: the previous slice, 1: the cell's own, between: a blend
    };
    struct StencilCell {
        int di, dj;       // relative to the cell
        float w;          // the taps' summed corner weights there
    };

    static Read read(float du, float dv, float w) {
        const float fa = std::floor(du), fb = std::floor(dv);
        return Read{int(fa), int(fb), du - fa, dv - fb, w};
    }
    void narrow(const Read& r) {
        lo_ = std::max(lo_, -r.di);
        hi_ = std::min(hi_, nu_ - 1 - r.di);
    }
    bool rowInside(int j, const Read& r) const { return j + r.dj >= 0 && j + r.dj + 1 < nv_; }
    void addToStencil(int di, int dj, double w) {
        if (w == 0.0) return;
        for (StencilCell& c : stencil_)
            if (c.di == di && c.dj == dj) {
                c.w = float(double(c.w) + w);
                return;
            }
        stencil_.push_back({di, dj, float(w)});
    }

    kernel::CpuPropagationKernel& k_;
    int nu_, nv_;
    bool usable_ = false;
    std::vector<SigmaRead> sigma_;
    std::vector<Read> taps_;
    std::vector<StencilCell> stencil_;
    int lo_ = 0, hi_ = 0;
    float atten_[3] = {1.0f, 1.0f, 1.0f};
    int planes_ = 1;   // of the extinction the row reads: 4 with per-material transport
    float step_world_ = 0.0f;
};

// Bilinear read between cell centres of one slice (nu x nv cells, `stride` floats between rows),
// 0 beyond it, as vx_prop_sigma_slice reads the extinction; (ga, gb) is the point less half a
// cell. Indices are clamped, so that SIMD lanes may gather every corner and drop the outside ones.
inline float cellOrZero(const float* slice, int nu, int nv, int stride, int a, int b) {
    const bool inside = a >= 0 && b >= 0 && a < nu && b < nv;
    const float value = slice[inside ? b * stride + a : 0];
    return inside ? value : 0.0f;
}
inline float bilinearOrZero(const float* slice, int nu, int nv, int stride, float ga, float gb) {
    const float fa = std::floor(ga), fb = std::floor(gb);
    const int ia = int(fa), ib = int(fb);
    return VX_BILERP(cellOrZero(slice, nu, nv, stride, ia, ib), cellOrZero(slice, nu, nv, stride, ia + 1, ib),
                     cellOrZero(slice, nu, nv, stride, ia, ib + 1), cellOrZero(slice, nu, nv, stride, ia + 1, ib + 1), ga - fa,
                     gb - fb);
}

// The CPU's batch form of vx_prop_cell for a point or spot light's sweep (Q.per_cell_flow),
// unperturbed, on the slices past the one next to the light's plane. Each cell steps back along
// its own ray from the light, so its reads land at offsets of its own (gathers), but every cell
// goes through the same arithmetic: SIMD lanes over a row, in vx_prop_cell's order, and each
// cell's weight as vx_prop_weight gives it. A lane whose step crosses more than kMaxPieces cells
// sideways, or whose blur taps read beyond the slice (where the kernel reads the light itself), is
// redone by vx_prop_cell, as is every cell of the first slice past the light's plane and of a
// sweep that blends two axes (its weight needs the angles of vx_sweep_weight).
class FlowRowBatch {
public:
    FlowRowBatch(kernel::CpuPropagationKernel& k, int nu, int nv) : k_(k), nu_(nu), nv_(nv) {
        const kernel::VxPropParams& Q = k.Q;
        axis_ = Q.axis;
        u_ = k.vx_axis_u(axis_);
        v_ = k.vx_axis_v(axis_);
        // (A slice of at least 2 x 2 cells: a lane reading beyond it gathers at index 0, whose
        // bilinear corners must still lie in the slice.)
        // (Per-material transport runs per cell: a point light's indirect sweep through a 2D
        // transfer function's regions.)
        usable_ = Q.per_cell_flow != 0 && Q.eye_sweep == 0 && Q.source_sweep == 0 && Q.blend_axes == 0 &&
                  Q.transport_planes == 0 && !k.vx_perturbed() && Q.strides[u_] == 1 && nu >= 2 && nv >= 2;
        const float r_min = k.vx_prop_r_min();
        r_min2_ = r_min * r_min;
    }

    // Row j's values (channels floats per cell) into `out` and its cells' weights into `weight`.
    void row(int j, int prev, float* out, float* weight) const {
        const kernel::VxPropParams& Q = k_.Q;
        const float dir = float(Q.direction);
        const float fa = float(Q.slice) + 0.5f - Q.source[axis_];   // the flow's component along the sweep
        const bool lanes = usable_ && prev >= 0 && prev < Q.dims[axis_] && dir * fa > 0.0f &&
                           dir * (float(prev) + 0.5f - Q.source[axis_]) > 0.0f;
        if (!lanes) {
            for (int i = 0; i < nu_; ++i) redo(i, j, out, weight);
            return;
        }
        for (int base = 0; base < nu_; base += kMaxRow) {
            Lanes l;
            l.n = std::min(kMaxRow, nu_ - base);
            if (axis_ == 0)
                steps<0>(j, base, prev, fa, l, weight + base);
            else if (axis_ == 1)
                steps<1>(j, base, prev, fa, l, weight + base);
            else
                steps<2>(j, base, prev, fa, l, weight + base);
            if (Q.channels == 1)
                transport<1>(l, out + base);
            else
                transport<3>(l, out + size_t(base) * 3);
            for (int q = 0; q < l.n; ++q)
                if (l.state[q] == kRedo) redo(base + q, j, out, weight);
        }
    }

private:
    static constexpr int kMaxRow = 256;
    static constexpr int kMaxPieces = 4;   // the default cone's sweeps reach slope 4 (Q.max_slope)
    enum : int { kLanes, kDark, kRedo };

    // A run of up to kMaxRow cells of a row, one SIMD lane each.
    struct Lanes {
        int n = 0;
        float pu[kMaxRow], pv[kMaxRow];   // where the cell's step starts, on the previous slice
        float radius[kMaxRow], tau[kMaxRow];
        int state[kMaxRow];
        float incoming[3][kMaxRow] = {};
    };

    // Each cell's step back to the previous slice, its optical depth (vx_prop_cell's composite
    // trapezoid), its blur radius and its weight (vx_prop_weight without blending). The sweep's
    // axis is a template argument, so that x, y and z of a step are known without a select.
    template <int Axis>
    void steps(int j, int base, int prev, float fa, Lanes& l, float* weight) const {
        constexpr int U = Axis == 0 ? 1 : 0, V = Axis == 2 ? 1 : 2;   // vx_axis_u, vx_axis_v
        const kernel::VxPropParams& Q = k_.Q;
        const int nu = nu_, nv = nv_, n = l.n;
        const int sv = Q.strides[V];
        const float* sigma_here = k_.prop_sigma.data + size_t(Q.slice) * size_t(Q.strides[Axis]);
        const float* sigma_prev = k_.prop_sigma.data + size_t(prev) * size_t(Q.strides[Axis]);
        // Between the two slices the lower one is where the trilinear reads start.
        const float* sigma_low = Q.direction > 0 ? sigma_prev : sigma_here;
        const float* sigma_high = Q.direction > 0 ? sigma_here : sigma_prev;
        const float den = std::max(std::abs(fa * Q.flow), 1e-6f), ba = fa * Q.flow / den;
        const float fv = float(j) + 0.5f - Q.source[V], bv = fv * Q.flow / den;
        const float su = Q.source[U], slope_limit = float(Q.max_slope) * (std::abs(fa) + 1.0f);
        const float pa = float(Q.slice) + 0.5f - ba, flow = Q.flow, blur_tan = Q.blur_tan, w0 = Q.weight, r_min2 = r_min2_;
        const glm::mat3 m(Q.grid_to_world);
        float* __restrict pu = l.pu;
        float* __restrict pv = l.pv;
        float* __restrict radius = l.radius;
        float* __restrict tau = l.tau;
        int* __restrict state = l.state;
        float bu[kMaxRow], sum[kMaxRow], step_world[kMaxRow];
        int pieces[kMaxRow];
#pragma omp simd
        for (int q = 0; q < n; ++q) {
            const int i = base + q;
            const float fu = float(i) + 0.5f - su;
            bu[q] = fu * flow / den;
            float f[3], b[3];   // x, y, z
            f[Axis] = fa, f[U] = fu, f[V] = fv;
            b[Axis] = ba, b[U] = bu[q], b[V] = bv;
            const float fx = f[0], fy = f[1], fz = f[2], bx = b[0], by = b[1], bz = b[2];
            pu[q] = float(i) + 0.5f - bu[q];
            pv[q] = float(j) + 0.5f - bv;
            const float wx = m[0][0] * bx + m[1][0] * by + m[2][0] * bz, wy = m[0][1] * bx + m[1][1] * by + m[2][1] * bz,
                        wz = m[0][2] * bx + m[1][2] * by + m[2][2] * bz;
            step_world[q] = std::sqrt(wx * wx + wy * wy + wz * wz);
            radius[q] = std::sqrt(bx * bx + by * by + bz * bz) * blur_tan;
            pieces[q] = std::max(int(std::ceil(std::max(std::abs(bu[q]), std::abs(bv)) - 1e-3f)), 1);
            const bool dark = std::max(std::abs(fu), std::abs(fv)) > slope_limit;
            state[q] = dark ? kDark : (pieces[q] <= kMaxPieces ? kLanes : kRedo);
            const float ax = std::abs(fx), ay = std::abs(fy), az = std::abs(fz);
            const int principal = az >= ay && az >= ax ? 2 : (ay >= ax ? 1 : 0);
            const float rx = m[0][0] * fx + m[1][0] * fy + m[2][0] * fz, ry = m[0][1] * fx + m[1][1] * fy + m[2][1] * fz,
                        rz = m[0][2] * fx + m[1][2] * fy + m[2][2] * fz;
            weight[q] = w0 * (principal == Axis ? 1.0f : 0.0f) / std::max(rx * rx + ry * ry + rz * rz, r_min2);
        }
#pragma omp simd
        for (int q = 0; q < n; ++q)
            sum[q] = 0.5f * (sigma_here[j * sv + base + q] + bilinearOrZero(sigma_prev, nu, nv, sv, pu[q] - 0.5f, pv[q] - 0.5f));
        // The inner points of a step longer than a cell sideways: trilinear between the two slices,
        // as far as the run's longest step needs (a light far away needs none).
        int most = 1;
#pragma omp simd reduction(max : most)
        for (int q = 0; q < n; ++q) most = std::max(most, state[q] == kLanes ? pieces[q] : 1);
        for (int piece = 1; piece < most; ++piece) {
#pragma omp simd
            for (int q = 0; q < n; ++q) {
                const float f = float(piece) / float(pieces[q]);
                const float ga = pa + ba * f - 0.5f, gu = pu[q] + bu[q] * f - 0.5f, gv = pv[q] + bv * f - 0.5f;
                const float t = ga - std::floor(ga);
                const float inner = glm::mix(bilinearOrZero(sigma_low, nu, nv, sv, gu, gv), bilinearOrZero(sigma_high, nu, nv, sv, gu, gv), t);
                sum[q] += piece < pieces[q] ? inner : 0.0f;
            }
        }
#pragma omp simd
        for (int q = 0; q < n; ++q) tau[q] = sum[q] * step_world[q] / float(pieces[q]);
    }

    // The light a run of cells takes in from the previous slice, transmitted over its step, into
    // `out` (C floats per cell): the blur taps (one, unblurred, for direct light) as bilinear reads
    // around each cell's own point, every channel, times e^-(atten tau).
    template <int C>
    void transport(Lanes& l, float* __restrict out) const {
        const kernel::VxPropParams& Q = k_.Q;
        const int nu = nu_, nv = nv_, n = l.n, row = nu_ * C;
        // The previous slice from each corner of a bilinear read: one 32-bit index for all four.
        const float* c00 = k_.prop_prev.data;
        const float *c10 = c00 + C, *c01 = c00 + row, *c11 = c00 + row + C;
        const float* __restrict pu = l.pu;
        const float* __restrict pv = l.pv;
        const float* __restrict radius = l.radius;
        int* __restrict state = l.state;
        for (int t = 0; t < Q.tap_count; ++t) {
            const float ox = Q.taps[t].offset.x, oy = Q.taps[t].offset.y, w = Q.taps[t].weight;
            for (int c = 0; c < C; ++c) {
                float* __restrict incoming = l.incoming[c];
#pragma omp simd
                for (int q = 0; q < n; ++q) {
                    const float ga = pu[q] + radius[q] * ox - 0.5f, gb = pv[q] + radius[q] * oy - 0.5f;
                    const float fa = std::floor(ga), fb = std::floor(gb);
                    const int ia = int(fa), ib = int(fb);
                    const bool inside = ia >= 0 && ib >= 0 && ia + 1 < nu && ib + 1 < nv;
                    state[q] = !inside && state[q] == kLanes ? kRedo : state[q];
                    const int at = inside ? ib * row + ia * C + c : 0;
                    incoming[q] = kernel::vx_radiance_add(
                        incoming[q], w * VX_BILERP(c00[at], c10[at], c01[at], c11[at], ga - fa, gb - fb));
                }
            }
        }
        for (int c = 0; c < C; ++c) {
            const float kc = Q.atten[c];
            const float* __restrict incoming = l.incoming[c];
            const float* __restrict tau = l.tau;
#pragma omp simd
            for (int q = 0; q < n; ++q) out[q * C + c] = state[q] == kDark ? 0.0f : incoming[q] * k_.vx_exp(-kc * tau[q]);
        }
    }

    void redo(int i, int j, float* out, float* weight) const {
        const glm::vec3 value = k_.vx_prop_cell(i, j);
        for (int ch = 0; ch < k_.Q.channels; ++ch) out[size_t(i) * k_.Q.channels + ch] = value[ch];
        weight[i] = k_.vx_prop_weight(i, j);
    }

    kernel::CpuPropagationKernel& k_;
    int nu_, nv_;
    int axis_ = 0, u_ = 0, v_ = 0;
    bool usable_ = false;
    float r_min2_ = 0.0f;
};

}  // namespace

void propagateCpu(const PropagationPass& pass, IlluminationVolume& volume, CpuSweepScratch& scratch) {
    const kernel::VxPropParams& first = pass.sweeps.front();
    const glm::ivec3 dims = first.dims;
    const int channels = first.channels;
    kernel::CpuPropagationKernel axes;
    const int axis = first.axis, u = axes.vx_axis_u(axis), v = axes.vx_axis_v(axis);
    const int nu = dims[u], nv = dims[v], slices = dims[axis];
    const bool eye = first.eye_sweep != 0;
    float* block = volume.values.data() + pass.offset;   // RGB per cell

    // The pass reads the extinction (and the eye input) once for all its lights: for an x sweep,
    // one slice-major copy shared by every light (and kept for the grid's next x pass), and one
    // result added back at the end.
    const SliceMajor layout{dims};
    const bool x_major = axis == 0;
    const std::vector<float>* sigma = pass.sigma;
    if (x_major) {
        sigma = &slicedSigma(pass, layout, scratch);
        if (pass.input) layout.toSlices(pass.input->data(), 3, scratch.input);
        resizeInHugePages(scratch.result, size_t(dims.x) * dims.y * dims.z * 3);   // every cell is written: no need to clear it
    }
    const glm::ivec3 stride = x_major ? glm::ivec3(dims.z * dims.y, 1, dims.y) : glm::ivec3(1, dims.x, dims.x * dims.y);
    assert(stride[u] == 1);   // rows are contiguous: the row batch and the row writes below rely on it
    // Where a cell's RGB goes: the x-major result or the block itself.
    float* out = x_major ? scratch.result.data() : block;

    // One lane per light: its own kernel parameters and its own pair of 2D slice buffers.
    struct Lane {
        kernel::CpuPropagationKernel k;
        std::vector<float> prev, cur;
        std::unique_ptr<RowBatch> batch;
        std::unique_ptr<FlowRowBatch> flow;
    };
    std::vector<std::unique_ptr<Lane>> lanes;
    for (const kernel::VxPropParams& Q : pass.sweeps) {
        auto lane = std::make_unique<Lane>();
        lane->k.P = *pass.march;
        lane->k.Q = Q;
        lane->k.Q.strides = stride;
        if (pass.noise) lane->k.noise = *pass.noise;
        lane->k.prop_sigma = *sigma;
        if (pass.input) lane->k.prop_in = x_major ? scratch.input : *pass.input;
        lane->prev.assign(size_t(nu) * nv * channels, 0.0f);
        lane->cur.assign(lane->prev.size(), 0.0f);
        lane->batch = std::make_unique<RowBatch>(lane->k, nu, nv);
        lane->flow = std::make_unique<FlowRowBatch>(lane->k, nu, nv);
        lanes.push_back(std::move(lane));
    }

    for (int step = 0; step < slices; ++step) {
        const int slice = first.direction > 0 ? step : slices - 1 - step;
        for (auto& lane : lanes) {
            lane->k.Q.slice = slice;
            lane->k.prop_prev = lane->prev;
        }
        const int previous = slice - first.direction;
        tbb::parallel_for(tbb::blocked_range<int>(0, nv), [&](const tbb::blocked_range<int>& rows) {
            std::vector<float> rgb(size_t(nu) * 3);   // the row's light from every lane of the pass
            std::vector<float> weights(nu);            // a point or spot light's weight per cell
            for (int j = rows.begin(); j < rows.end(); ++j) {
                std::fill(rgb.begin(), rgb.end(), 0.0f);
                for (auto& lane : lanes) {
                    kernel::CpuPropagationKernel& k = lane->k;
                    float* row = &lane->cur[size_t(j) * nu * channels];
                    const int step = channels == 1 ? 0 : 1;   // a direct sweep's one value feeds every channel
                    if (!eye && k.Q.per_cell_flow != 0) {   // a point or spot light: each cell's own weight
                        lane->flow->row(j, previous, row, weights.data());   // per cell where it cannot batch
#pragma omp simd
                        for (int i = 0; i < nu; ++i) {
                            const float* slot = row + size_t(i) * channels;
                            float* sum = &rgb[size_t(i) * 3];
                            const float w = weights[size_t(i)];
                            for (int c = 0; c < 3; ++c) sum[c] = kernel::vx_radiance_add(sum[c], k.vx_prop_added(w, c, slot[c * step]));
                        }
                        continue;
                    }
                    int first_batched = 0, last_batched = 0;
                    lane->batch->row(j, previous, row, first_batched, last_batched);
                    // The cells the batch left (the row's ends, or the whole row): the per-cell kernel.
                    const auto perCell = [&](int from, int to) {
                        for (int i = from; i < to; ++i) {
                            const glm::vec3 value = k.vx_prop_cell(i, j);
                            for (int ch = 0; ch < channels; ++ch) row[size_t(i) * channels + ch] = value[ch];
                        }
                    };
                    perCell(0, first_batched);
                    perCell(std::max(first_batched, last_batched), nu);
                    // One weight for the row (the eye sweep's is 1).
                    const float w = eye ? 1.0f : k.Q.weight;
#pragma omp simd
                    for (int i = 0; i < nu; ++i) {
                        const float* slot = row + size_t(i) * channels;
                        float* sum = &rgb[size_t(i) * 3];
                        for (int c = 0; c < 3; ++c) sum[c] = kernel::vx_radiance_add(sum[c], k.vx_prop_added(w, c, slot[c * step]));
                    }
                }
                // The row's cells are contiguous in `out` (u is the fastest axis of either layout).
                // Integer offsets: a float dot product is exact only below 2^24 cells.
                float* cells = out + (size_t(slice) * size_t(stride[axis]) + size_t(j) * size_t(stride[v])) * 3;
                if (x_major || eye) {
                    std::copy(rgb.begin(), rgb.end(), cells);
                } else {
#pragma omp simd
                    for (size_t m = 0; m < rgb.size(); ++m) cells[m] = kernel::vx_radiance_add(cells[m], rgb[m]);
                }
            }
        });
        for (auto& lane : lanes) std::swap(lane->prev, lane->cur);
    }
    if (!x_major) return;
    layout.forEachCell([&](size_t n, size_t s) {
        for (int ch = 0; ch < 3; ++ch) {
            float& cell = block[n * 3 + ch];
            cell = eye ? scratch.result[s * 3 + ch] : kernel::vx_radiance_add(cell, scratch.result[s * 3 + ch]);
        }
    });
}

}  // namespace voxlux
