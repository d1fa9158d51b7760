// The propagation's sweeps (vx_propagation.h: Ropinski 2010's slice-by-slice transport with
// Sunden 2015's axis blending) compiled as C++ over the kernel's data and shared functions
// (cpu_kernel_data.h), as cpu_kernel.h compiles the march. A struct of its own, so that editing
// the sweeps' kernel text recompiles only what runs them, never the march.
#pragma once
#include "kernel/cpu_kernel_data.h"

namespace voxlux::kernel {

// Its blocks' C++ bytes are their std140 bytes (vx_types.h's layout rule).
static_assert(sizeof(VxTap) == 16);
static_assert(sizeof(VxPropParams) % 16 == 0);
VX_LINE_ALIGNED(VxPropParams, grid_to_world);
VX_LINE_ALIGNED(VxPropParams, world_to_grid);
VX_LINE_ALIGNED(VxPropParams, dims);
VX_LINE_ALIGNED(VxPropParams, strides);
VX_LINE_ALIGNED(VxPropParams, source);
VX_LINE_ALIGNED(VxPropParams, atten);
VX_LINE_ALIGNED(VxPropParams, tint);
VX_LINE_ALIGNED(VxPropParams, light);
VX_LINE_ALIGNED(VxPropParams, taps);
static_assert(sizeof(VxPropagationMarch) % 16 == 0);
VX_LINE_ALIGNED(VxPropagationMarch, illum_dims);
VX_LINE_ALIGNED(VxPropagationMarch, chroma_dims);

struct CpuPropagationKernel : CpuKernelData {
#include "lighting/propagation/kernel/vx_propagation.h"
};

}  // namespace voxlux::kernel
