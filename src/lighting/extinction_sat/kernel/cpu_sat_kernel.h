// The extinction SAT's light passes (vx_sat.h: the summed-area table's exact box sums, the
// AO shells and the shadow cones of cuboids, Schlegel 2011) compiled as C++ over the kernel's
// data and accessors (cpu_kernel_data.h), as cpu_kernel.h compiles the march. A struct of its own,
// so that editing the light passes' kernel text recompiles only what runs them, never the march.
#pragma once
#include "kernel/cpu_kernel_data.h"

namespace voxlux::kernel {

// Its blocks' C++ bytes are their std140 bytes (vx_types.h's layout rule).
static_assert(sizeof(VxSatParams) % 16 == 0);
VX_LINE_ALIGNED(VxSatParams, light_to_world);
VX_LINE_ALIGNED(VxSatParams, world_to_light);
VX_LINE_ALIGNED(VxSatParams, dims);
VX_LINE_ALIGNED(VxSatParams, quantum);
static_assert(sizeof(VxSatMarch) % 16 == 0);
VX_LINE_ALIGNED(VxSatMarch, cache_dims);

struct CpuSatKernel : CpuKernelData {
#include "lighting/extinction_sat/kernel/vx_sat.h"
};

}  // namespace voxlux::kernel
