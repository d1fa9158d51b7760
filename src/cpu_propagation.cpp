#include "cpu_propagation.h"

#include <tbb/parallel_for.h>

#include "cpu_kernel.h"

namespace voxlux {
namespace {

// A sweep reads and writes whole slices. For y and z sweeps a slice is rows of x, contiguous in
// the volume's layout; an x sweep's slice is one float per cache line there, so it runs on copies
// laid out slice by slice (x-major: index (x * nz + z) * ny + y) and the result is added back.
struct SliceMajor {
    glm::ivec3 dims;
    size_t natural(int x, int y, int z) const { return (size_t(z) * dims.y + y) * dims.x + x; }
    size_t sliced(int x, int y, int z) const { return (size_t(x) * dims.z + z) * dims.y + y; }

    // Copies `channels` floats per cell from natural to x-major order.
    std::vector<float> toSlices(const float* in, int channels) const {
        std::vector<float> out(size_t(dims.x) * dims.y * dims.z * channels);
        tbb::parallel_for(0, dims.z, [&](int z) {
            for (int y = 0; y < dims.y; ++y)
                for (int x = 0; x < dims.x; ++x)
                    for (int c = 0; c < channels; ++c) out[sliced(x, y, z) * channels + c] = in[natural(x, y, z) * channels + c];
        });
        return out;
    }
};

}  // namespace

void propagateCpu(const SweepJob& job, IlluminationVolume& volume) {
    kernel::CpuKernel k;
    k.P = *job.march;
    k.Q = job.params;
    k.noise = job.noise ? job.noise->data() : nullptr;
    const glm::ivec3 dims(k.Q.dims);
    const int channels = k.Q.dims.w;
    const int axis = k.Q.slice.x, u = k.vx_axis_u(axis), v = k.vx_axis_v(axis);
    const int nu = dims[u], nv = dims[v], slices = dims[axis];
    const bool eye = k.Q.flow.w > 0.5f;
    const float weight = k.Q.flow.z;
    float* block = volume.values.data() + job.offset;

    const SliceMajor layout{dims};
    const bool x_major = axis == 0;
    std::vector<float> sigma, input, result;
    if (x_major) {
        sigma = layout.toSlices(job.sigma->data(), 1);
        if (job.input) input = layout.toSlices(job.input->data(), 3);
        result.resize(sigma.size() * channels);
        k.Q.strides = glm::ivec4(dims.z * dims.y, 1, dims.y, 0);
    } else {
        k.Q.strides = glm::ivec4(1, dims.x, dims.x * dims.y, 0);
    }
    k.prop_sigma = x_major ? sigma.data() : job.sigma->data();
    k.prop_in = !job.input ? nullptr : x_major ? input.data() : job.input->data();
    // Where a cell's values go: the x-major result (added back below) or the block itself.
    float* out = x_major ? result.data() : block;
    const glm::ivec3 stride(k.Q.strides);

    std::vector<float> prev(size_t(nu) * nv * channels), cur(prev.size());
    for (int step = 0; step < slices; ++step) {
        k.Q.slice.z = k.Q.slice.y > 0 ? step : slices - 1 - step;
        k.prop_prev = prev.data();
        tbb::parallel_for(0, nv, [&](int j) {
            glm::ivec3 c;
            c[axis] = k.Q.slice.z;
            c[v] = j;
            for (int i = 0; i < nu; ++i) {
                c[u] = i;
                const glm::vec3 value = k.vx_prop_cell(i, j);
                float* slot = &cur[(size_t(j) * nu + i) * channels];
                float* cell = out + size_t(glm::dot(glm::vec3(c), glm::vec3(stride))) * channels;
                for (int ch = 0; ch < channels; ++ch) {
                    slot[ch] = value[ch];
                    cell[ch] = x_major || eye ? value[ch] : cell[ch] + weight * value[ch];
                }
            }
        });
        std::swap(prev, cur);
    }
    if (!x_major) return;
    tbb::parallel_for(0, dims.z, [&](int z) {
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                for (int ch = 0; ch < channels; ++ch) {
                    float& cell = block[layout.natural(x, y, z) * channels + ch];
                    const float value = result[layout.sliced(x, y, z) * channels + ch];
                    cell = eye ? value : cell + weight * value;
                }
    });
}

}  // namespace voxlux
