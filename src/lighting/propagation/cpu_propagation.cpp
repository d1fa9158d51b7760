// The CPU's propagation sweeps (vx_propagation.h: Ropinski 2010's slice-by-slice transport): the
// slices in order, each slice's rows in parallel (TBB), every light of the pass in the same row.
// A row runs through the kernel's row batches where its cells can (vx_prop_row_run for a sweep
// whose cells step back alike, vx_prop_flow_run for a point or spot light's), and through the
// per-cell kernel vx_prop_cell elsewhere. Per sweep and cell: a few bilinear reads of the
// extinction and of the previous slice (one per blur-stencil cell), one exp; an x sweep also
// copies its slices into and out of x-major order.
#include "lighting/propagation/cpu_propagation.h"

#include <algorithm>
#include <cassert>
#include <memory>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/huge_pages.h"
#include "lighting/propagation/kernel/cpu_propagation_kernel.h"

namespace voxlux {
namespace {

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

// GCC only: no unroll-and-jam, which would fuse two of the directional row batch's SIMD loops and
// read the second one's contiguous floats as gathers.
#if defined(__GNUC__) && !defined(__clang__)
#define VOXLUX_NO_UNROLL_AND_JAM gnu::optimize("no-loop-unroll-and-jam")
#else
#define VOXLUX_NO_UNROLL_AND_JAM
#endif

// Runs `run` with every call in it inlined, recursively: the kernel's functions and vector
// operators then all inline into the SIMD loops of a row batch, where the inliner's growth limits
// would leave calls, and into the per-cell kernel at a row's ends (the directional sweeps then take
// 0.64-0.90 of their time before, docs/accuracy-propagation.md).
template <class Run>
[[gnu::flatten, VOXLUX_NO_UNROLL_AND_JAM]] void flattened(Run&& run) {
    run();
}

// Cell (i, j) of the slice by the per-cell kernel, into `out` (channels floats per cell).
void cellByKernel(kernel::CpuPropagationKernel& k, int i, int j, float* out) {
    const glm::vec3 value = k.vx_prop_cell(i, j);
    for (int ch = 0; ch < k.Q.channels; ++ch) out[size_t(i) * k.Q.channels + ch] = value[ch];
}

// A sweep whose every cell steps back alike (vx_prop_row_stencil says which): each row's cells
// [lo, hi) through the kernel's row batch (vx_prop_row_run), the row's ends, and every row whose
// reads leave the slice, through vx_prop_cell.
class RowBatch {
public:
    explicit RowBatch(kernel::CpuPropagationKernel& k) : k_(k) { k.vx_prop_row_stencil(stencil_); }

    // Row j's values (channels floats per cell) into `out`.
    void row(int j, int prev, float* out) const {
        const kernel::VxPropParams& Q = k_.Q;
        const int channels = Q.channels, nu = Q.dims[k_.vx_axis_u(Q.axis)];
        const bool batched = k_.vx_prop_row_fits(stencil_, j, prev);
        const int lo = batched ? stencil_.lo : nu, hi = batched ? stencil_.hi : nu;
        kernel::CpuPropagationKernel::VxPropRowRun run;
        for (int base = lo; base < hi; base += VX_PROP_RUN) {
            const int n = std::min(VX_PROP_RUN, hi - base);
            flattened([&] { k_.vx_prop_row_run(stencil_, j, prev, base, n, run); });
            std::copy_n(run.light, size_t(n) * channels, out + size_t(base) * channels);
        }
        flattened([&] {
            for (int i = 0; i < lo; ++i) cellByKernel(k_, i, j, out);
            for (int i = hi; i < nu; ++i) cellByKernel(k_, i, j, out);
        });
    }

private:
    kernel::CpuPropagationKernel& k_;
    kernel::CpuPropagationKernel::VxPropStencil stencil_;
};

// A point or spot light's sweep (Q.per_cell_flow): the rows of a slice the kernel's batch takes
// (vx_prop_flow_batches) in runs through it (vx_prop_flow_run), the lanes it leaves and every
// other row (the first slice past the light's plane, a sweep that blends two axes, perturbed
// media, per-material transport) through vx_prop_cell.
class FlowRowBatch {
public:
    FlowRowBatch(kernel::CpuPropagationKernel& k, int nu) : k_(k), nu_(nu) {}

    // Row j's values (channels floats per cell) into `out` and its cells' weights into `weight`.
    void row(int j, int prev, float* out, float* weight) const {
        const int axis = k_.Q.axis, channels = k_.Q.channels;
        if (!k_.vx_prop_flow_batches(prev)) {
            flattened([&] {
                for (int i = 0; i < nu_; ++i) redo(i, j, out, weight);
            });
            return;
        }
        kernel::CpuPropagationKernel::VxPropRun run;
        for (int base = 0; base < nu_; base += VX_PROP_RUN) {
            const int n = std::min(VX_PROP_RUN, nu_ - base);
            // The axis as a constant, so that the kernel's vectors are read without selects; on a
            // copy of the kernel on the stack, whose array pointers the compiler then sees stay put
            // while the run is written: it hoists them out of the lanes' conditional reads.
            const auto runAlong = [&](auto axis_constant) {
                flattened([&] {
                    kernel::CpuPropagationKernel k = k_;
                    k.vx_prop_flow_run(decltype(axis_constant)::value, base, j, n, run);
                });
            };
            if (axis == 0)
                runAlong(std::integral_constant<int, 0>());
            else if (axis == 1)
                runAlong(std::integral_constant<int, 1>());
            else
                runAlong(std::integral_constant<int, 2>());
            float* values = out + size_t(base) * channels;
            for (int c = 0; c < channels; ++c)
                for (int l = 0; l < n; ++l) values[l * channels + c] = run.incoming[c * VX_PROP_RUN + l];
            std::copy_n(run.weight, n, weight + base);
            flattened([&] {
                for (int l = 0; l < n; ++l)
                    if (run.state[l] == VX_LANE_REDO) redo(base + l, j, out, weight);
            });
        }
    }

private:
    void redo(int i, int j, float* out, float* weight) const {
        cellByKernel(k_, i, j, out);
        weight[i] = k_.vx_prop_weight(i, j);
    }

    kernel::CpuPropagationKernel& k_;
    int nu_;
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
    // result per light group's block added back at the end.
    const SliceMajor layout{dims};
    const bool x_major = axis == 0;
    const std::vector<float>* sigma = pass.sigma;
    if (x_major) {
        sigma = &slicedSigma(pass, layout, scratch);
        if (pass.input) layout.toSlices(pass.input->data(), 3, scratch.input);
    }
    const glm::ivec3 stride = x_major ? glm::ivec3(dims.z * dims.y, 1, dims.y) : glm::ivec3(1, dims.x, dims.x * dims.y);
    assert(stride[u] == 1);   // rows are contiguous: the row batch and the row writes below rely on it
    // The blocks the pass's sweeps add into (light groups have one each), and each sweep's.
    std::vector<int> targets;
    std::vector<size_t> target_of;
    for (const kernel::VxPropParams& Q : pass.sweeps) {
        const auto at = std::find(targets.begin(), targets.end(), Q.block_first);
        target_of.push_back(size_t(at - targets.begin()));
        if (at == targets.end()) targets.push_back(Q.block_first);
    }
    const size_t cells = size_t(dims.x) * dims.y * dims.z;
    if (x_major) resizeInHugePages(scratch.result, cells * 3 * targets.size());   // every cell is written: no need to clear it
    // Where a cell's RGB goes: the x-major result or the block itself.
    const auto out = [&](size_t t) { return x_major ? scratch.result.data() + t * cells * 3 : block + targets[t]; };

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
        lane->batch = std::make_unique<RowBatch>(lane->k);
        lane->flow = std::make_unique<FlowRowBatch>(lane->k, nu);
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
            std::vector<float> rgbs(size_t(nu) * 3 * targets.size());   // the row's light from every lane of the pass, per block
            std::vector<float> weights(nu);            // a point or spot light's weight per cell
            for (int j = rows.begin(); j < rows.end(); ++j) {
                std::fill(rgbs.begin(), rgbs.end(), 0.0f);
                for (size_t l = 0; l < lanes.size(); ++l) {
                    Lane* lane = lanes[l].get();
                    float* rgb = rgbs.data() + target_of[l] * size_t(nu) * 3;
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
                    lane->batch->row(j, previous, row);
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
                const size_t row_at = (size_t(slice) * size_t(stride[axis]) + size_t(j) * size_t(stride[v])) * 3;
                for (size_t t = 0; t < targets.size(); ++t) {
                    float* row = out(t) + row_at;
                    const float* rgb = rgbs.data() + t * size_t(nu) * 3;
                    if (x_major || eye) {
                        std::copy_n(rgb, size_t(nu) * 3, row);
                    } else {
#pragma omp simd
                        for (size_t m = 0; m < size_t(nu) * 3; ++m) row[m] = kernel::vx_radiance_add(row[m], rgb[m]);
                    }
                }
            }
        });
        for (auto& lane : lanes) std::swap(lane->prev, lane->cur);
    }
    if (!x_major) return;
    for (size_t t = 0; t < targets.size(); ++t) {
        const float* result = out(t);
        layout.forEachCell([&](size_t n, size_t s) {
            for (int ch = 0; ch < 3; ++ch) {
                float& cell = block[size_t(targets[t]) + n * 3 + ch];
                cell = eye ? result[s * 3 + ch] : kernel::vx_radiance_add(cell, result[s * 3 + ch]);
            }
        });
    }
}

}  // namespace voxlux
