#include "cpu_propagation.h"

#include <tbb/parallel_for.h>

#include "cpu_kernel.h"

namespace voxlux {

void propagateCpu(const SweepJob& job, IlluminationVolume& volume) {
    kernel::CpuKernel k;
    k.P = *job.march;
    k.Q = job.params;
    k.noise = job.noise->data();
    k.prop_sigma = job.sigma->data();
    k.prop_in = job.input ? job.input->data() : nullptr;
    const glm::ivec3 dims(k.Q.dims);
    const int channels = k.Q.dims.w;
    const int axis = k.Q.slice.x, u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int nu = dims[u], nv = dims[v], slices = dims[axis];
    const bool eye = k.Q.flow.w > 0.5f;
    const float weight = k.Q.flow.z;
    std::vector<float> prev(size_t(nu) * nv * channels), cur(prev.size());
    float* out = volume.values.data() + job.offset;
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
                float* cell = out + ((size_t(c.z) * dims.y + c.y) * dims.x + c.x) * channels;
                for (int ch = 0; ch < channels; ++ch) {
                    slot[ch] = value[ch];
                    cell[ch] = eye ? value[ch] : cell[ch] + weight * value[ch];
                }
            }
        });
        std::swap(prev, cur);
    }
}

}  // namespace voxlux
