// The shared march kernel (shaders/vx_march.h) compiled as C++ over the kernel's data and shared
// functions (cpu_kernel_data.h), exactly as the GL backend compiles it (shaders/march.comp). Only
// what marches camera or shadow rays includes this: the march calls the lighting methods' hooks
// (generated vx_lighting.h), so editing a method's hook recompiles these objects alone.
#pragma once
#include "kernel/cpu_kernel_data.h"

namespace voxlux::kernel {

struct CpuKernel : CpuKernelData {
#include "vx_march.h"
};

}  // namespace voxlux::kernel

namespace voxlux {
// The march kernel bound to the march inputs' arrays.
inline kernel::CpuKernel bindCpuKernel(const KernelInputs& inputs) { return {bindKernelData(inputs)}; }
}  // namespace voxlux
