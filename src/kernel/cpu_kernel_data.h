// The kernel's data and the functions every pass shares (shaders/vx_*.h compiled as C++): the
// headers are included inside this struct, so their functions become members and the backend data
// accessors below are in scope, exactly as the GL backend provides them as buffer reads. It holds
// the sampling, the brick walk, motion, noise, surface shading and the pixel, not the march
// (cpu_kernel.h) nor its lighting hooks, so the light passes, the reference and the tools that
// build on it do not recompile when a method's march hook changes.
#pragma once
#include <array>
#include <string_view>
#include <vector>

#include "kernel/kernel_inputs.h"
#include "kernel/kernel_types.h"

namespace voxlux::kernel {

// Reports an index outside one of the kernel's arrays and aborts (VX_BOUNDS_CHECK builds).
[[noreturn]] void vx_bounds_trap(const char* what, int index, int size);

// One array the kernel reads: its first element and length. A VX_BOUNDS_CHECK build (the
// sanitizer build the tests run in) traps every index outside it; other builds read unchecked.
template <class T>
struct KernelArray {
    const T* data = nullptr;
    int size = 0;

    KernelArray() = default;
    KernelArray(const std::vector<T>& v) : data(v.data()), size(int(v.size())) {}
    KernelArray(const T* first, size_t count) : data(first), size(int(count)) {}

    VX_INLINE T at(int i, const char* what) const {
        VX_CHECK_INDEX(i, size, what);
        (void)what;
        return data[i];
    }
};

struct CpuKernelData {
    // The parameter blocks, arrays and accessors of the kernel contract (generated,
    // cmake/kernel_contract.cmake): P, L, a pass's block; density, page, lights, cache, ...
#include "vx_cpu_data.inc"

    // The atlas's vector grids, one block on GL (vx_gl_bindings.glsl), arrays of their own here.
    KernelArray<float> color;              // 3 floats per voxel
    KernelArray<float> surface;            // 1 float per voxel
    KernelArray<float> velocity;           // 3 floats per voxel
    KernelArray<float> holdout;            // the depth holdouts' camera-space Z per pixel (shares the block on GL)
    // The volumes of a scene of several: a uniform block on GL (vx_gl_bindings.glsl).
    KernelArray<VxVolume> volumes;
    VxVolume vx_placed_volume(int i) const { return volumes.at(i, "volume"); }
    vec3 vx_atlas_color(int i) const {
        return vec3(color.at(3 * i, "atlas colour"), color.at(3 * i + 1, "atlas colour"), color.at(3 * i + 2, "atlas colour"));
    }
    float vx_atlas_surface(int i) const { return surface.at(i, "atlas surface weight"); }
    float vx_holdout(int i) const { return holdout.at(i, "holdout depth"); }
    vec3 vx_atlas_velocity(int i) const {
        return vec3(velocity.at(3 * i, "atlas velocity"), velocity.at(3 * i + 1, "atlas velocity"), velocity.at(3 * i + 2, "atlas velocity"));
    }

#include "vx_dda.h"
#include "vx_grid.h"
#include "vx_motion.h"
#include "vx_optics.h"
#include "vx_pixel.h"
#include "vx_surface.h"
#include "vx_volumes.h"
};
// The march (cpu_kernel.h) and the lighting methods' own kernel text (CpuSatKernel,
// CpuPropagationKernel in their kernel/ folders) compile into structs derived from this one.

}  // namespace voxlux::kernel

namespace voxlux {
// The kernel data bound to the march inputs' arrays (a light pass's own members stay unset).
kernel::CpuKernelData bindKernelData(const KernelInputs& inputs);
}  // namespace voxlux
