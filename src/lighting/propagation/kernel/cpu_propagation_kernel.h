// The propagation's sweeps (vx_propagation.h: Ropinski 2010's slice-by-slice transport with
// Sunden 2015's axis blending) compiled as C++ over the march kernel's accessors and functions,
// as cpu_kernel.h compiles the march. A struct of its own, so that editing the sweeps' kernel text
// recompiles only what runs them, never the march.
#pragma once
#include "kernel/cpu_kernel.h"

namespace voxlux::kernel {

struct CpuPropagationKernel : CpuKernel {
#include "lighting/propagation/kernel/vx_propagation.h"
};

}  // namespace voxlux::kernel
