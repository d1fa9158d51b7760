#include "lighting/propagation/cpu_propagation.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/huge_pages.h"
#include "kernel/cpu_kernel.h"

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

// The slice-major copy of the pass's extinction: the one kept for its grid, or made into the slot
// used least recently.
const std::vector<float>& slicedSigma(const PropagationPass& pass, const SliceMajor& layout, CpuSweepScratch& scratch) {
    CpuSweepScratch::SlicedSigma* slot = nullptr;
    for (auto& s : scratch.sigma)
        if (pass.sigma_generation != 0 && s.generation == pass.sigma_generation && s.values.size() == pass.sigma->size()) slot = &s;
    if (!slot) {
        slot = scratch.sigma[0].last_use <= scratch.sigma[1].last_use ? &scratch.sigma[0] : &scratch.sigma[1];
        slot->generation = 0;   // stays 0 if the copy throws
        layout.toSlices(pass.sigma->data(), 1, slot->values);
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
    RowBatch(kernel::CpuKernel& k, int nu, int nv) : k_(k), nu_(nu), nv_(nv) {
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
        float tau[kMaxRow];
        for (int base = lo_; base < hi_; base += kMaxRow) {
            const int n = std::min(kMaxRow, hi_ - base);
            std::fill(tau, tau + n, 0.0f);
            for (const SigmaRead& r : sigma_) {
                // Row starts; the offset di (negative at a row's start) goes into the index, so
                // that no pointer is formed outside the arrays.
                const float* a0 = k_.prop_sigma.data + size_t(prev) * sa + size_t(j + r.at.dj) * sv;
                const float* b0 = k_.prop_sigma.data + size_t(Q.slice) * sa + size_t(j + r.at.dj) * sv;
                const float ta = r.at.ta, tb = r.at.tb, f = r.slice, w = r.at.w;
                const int di = r.at.di;
#pragma omp simd
                for (int q = 0; q < n; ++q) {
                    const int i = base + q + di;
                    const float in_prev = VX_BILERP(a0[i], a0[i + 1], a0[i + sv], a0[i + sv + 1], ta, tb);
                    const float in_here = VX_BILERP(b0[i], b0[i + 1], b0[i + sv], b0[i + sv + 1], ta, tb);
                    tau[q] += w * glm::mix(in_prev, in_here, f);
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
                const float kc = atten_[c];
                if (Q.source_sweep == 0) {
#pragma omp simd
                    for (int q = 0; q < n; ++q) out[size_t(base + q) * channels + c] = acc[q * channels + c] * k_.vx_exp(-kc * tau[q]);
                    continue;
                }
                // A source sweep adds the cell's own source over the step, as vx_prop_cell does.
                const float* src = k_.prop_in.data + (size_t(Q.slice) * sa + size_t(j) * sv) * 3 + c;
                const float step = step_world_;
#pragma omp simd
                for (int q = 0; q < n; ++q) {
                    const float kt = kc * tau[q];
                    out[size_t(base + q) * channels + c] =
                        kernel::vx_radiance_add(acc[q * channels + c] * k_.vx_exp(-kt), src[size_t(base + q) * 3] * (step * k_.vx_exp_integral(kt)));
                }
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

    kernel::CpuKernel& k_;
    int nu_, nv_;
    bool usable_ = false;
    std::vector<SigmaRead> sigma_;
    std::vector<Read> taps_;
    std::vector<StencilCell> stencil_;
    int lo_ = 0, hi_ = 0;
    float atten_[3] = {1.0f, 1.0f, 1.0f};
    float step_world_ = 0.0f;
};

}  // namespace

void propagateCpu(const PropagationPass& pass, IlluminationVolume& volume, CpuSweepScratch& scratch) {
    const kernel::VxPropParams& first = pass.sweeps.front();
    const glm::ivec3 dims = first.dims;
    const int channels = first.channels;
    kernel::CpuKernel axes;
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
        resizeInHugePages(scratch.result, sigma->size() * 3);   // every cell is written: no need to clear it
    }
    const glm::ivec3 stride = x_major ? glm::ivec3(dims.z * dims.y, 1, dims.y) : glm::ivec3(1, dims.x, dims.x * dims.y);
    assert(stride[u] == 1);   // rows are contiguous: the row batch and the row writes below rely on it
    // Where a cell's RGB goes: the x-major result or the block itself.
    float* out = x_major ? scratch.result.data() : block;

    // One lane per light: its own kernel parameters and its own pair of 2D slice buffers.
    struct Lane {
        kernel::CpuKernel k;
        std::vector<float> prev, cur;
        std::unique_ptr<RowBatch> batch;
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
            for (int j = rows.begin(); j < rows.end(); ++j) {
                std::fill(rgb.begin(), rgb.end(), 0.0f);
                for (auto& lane : lanes) {
                    kernel::CpuKernel& k = lane->k;
                    float* row = &lane->cur[size_t(j) * nu * channels];
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
                    const glm::vec3 tint = k.Q.tint;
                    if (!eye && k.Q.per_cell_flow != 0) {   // a point or spot light: each cell's own weight
                        for (int i = 0; i < nu; ++i) {
                            const float w = k.vx_prop_weight(i, j);
                            for (int ch = 0; ch < 3; ++ch) {
                                float& sum = rgb[size_t(i) * 3 + ch];
                                sum = kernel::vx_radiance_add(sum, w * tint[ch] * row[size_t(i) * channels + (channels == 1 ? 0 : ch)]);
                            }
                        }
                        continue;
                    }
                    // One weight for the row: (w * tint) * light, as the per-cell form multiplies.
                    const float w = eye ? 1.0f : k.Q.weight;
                    const float wt0 = w * tint[0], wt1 = w * tint[1], wt2 = w * tint[2];
                    const int step = channels == 1 ? 0 : 1;
#pragma omp simd
                    for (int i = 0; i < nu; ++i) {
                        const float* slot = row + size_t(i) * channels;
                        float* sum = &rgb[size_t(i) * 3];
                        sum[0] = kernel::vx_radiance_add(sum[0], wt0 * slot[0]);
                        sum[1] = kernel::vx_radiance_add(sum[1], wt1 * slot[step]);
                        sum[2] = kernel::vx_radiance_add(sum[2], wt2 * slot[2 * step]);
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
