#include "kernel/cpu_kernel_data.h"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace voxlux {

[[noreturn]] void kernel::vx_bounds_trap(const char* what, int index, int size) {
    std::fprintf(stderr, "voxlux: kernel %s index %d outside [0, %d)\n", what, index, size);
    std::abort();
}

kernel::CpuKernelData bindKernelData(const KernelInputs& in) {
    kernel::CpuKernelData k;
    k.P = in.params;
    k.density = in.atlas->density;
    k.emission = in.atlas->emission;
    k.color = in.atlas->color;
    k.surface = in.atlas->surface;
    k.velocity = in.atlas->velocity;
    k.page = in.pages->entries;
    k.lights = in.lights;
    k.tf_lut = in.tf_lut;
    k.emission_lut = in.emission_lut;
    k.L = in.lighting.blocks;
    for (const KernelArrayRef& a : in.lighting.arrays)
        if (!k.vx_bind_array(a.block, a.data, a.bytes)) throw std::logic_error("the kernel has no array " + a.block);
    k.noise = in.noise;
    if (in.holdout) k.holdout = *in.holdout;
    k.volumes = in.volumes;
    return k;
}

}  // namespace voxlux
