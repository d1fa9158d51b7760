// The shared march kernel (shaders/vx_*.h) compiled as C++: the headers are included inside this
// struct, so their functions become members and the backend data accessors below are in scope,
// exactly as the GL backend provides them as buffer reads (shaders/march.comp).
#pragma once
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

struct CpuKernel {
    VxParams P{};
    KernelArray<float> density;
    KernelArray<float> emission;           // source-major channels (P.emission_source_floats each)
    KernelArray<float> color;              // 3 floats per voxel
    KernelArray<float> surface;            // 1 float per voxel
    KernelArray<float> velocity;           // 3 floats per voxel
    KernelArray<ivec4> page;
    KernelArray<VxLight> lights;
    KernelArray<vec4> tf_lut;
    KernelArray<vec4> emission_lut;        // VX_EMISSION_LUT_SIZE rows per emission source
    KernelArray<float> cache;              // light cache, P.cache_floats per cell
    VxSatParams S{};                       // light passes only
    KernelArray<uint> sat;
    KernelArray<float> illum;              // illumination volume (march)
    KernelArray<vec4> noise;               // perturbation table
    VxPropParams Q{};                      // propagation sweeps only
    KernelArray<float> prop_sigma;
    KernelArray<float> prop_prev;
    KernelArray<float> prop_in;

    float vx_atlas_density(int i) const { return density.at(i, "atlas density"); }
    float vx_atlas_emission(int i) const { return emission.at(i, "atlas emission"); }
    vec3 vx_atlas_color(int i) const {
        return vec3(color.at(3 * i, "atlas colour"), color.at(3 * i + 1, "atlas colour"), color.at(3 * i + 2, "atlas colour"));
    }
    float vx_atlas_surface(int i) const { return surface.at(i, "atlas surface weight"); }
    vec3 vx_atlas_velocity(int i) const {
        return vec3(velocity.at(3 * i, "atlas velocity"), velocity.at(3 * i + 1, "atlas velocity"), velocity.at(3 * i + 2, "atlas velocity"));
    }
    ivec4 vx_page_entry(int i) const { return page.at(i, "page table"); }
    VxLight vx_light(int i) const { return lights.at(i, "light"); }
    vec4 vx_tf_lut(int i) const { return tf_lut.at(i, "transfer LUT"); }
    vec4 vx_emission_lut(int i) const { return emission_lut.at(i, "emission LUT"); }
    float vx_cache(int i) const { return cache.at(i, "light cache"); }
    uint vx_sat_word(int i) const { return sat.at(i, "SAT"); }
    float vx_illum(int i) const { return illum.at(i, "illumination volume"); }
    vec4 vx_noise(int i) const { return noise.at(i, "noise table"); }
    float vx_prop_sigma(int i) const { return prop_sigma.at(i, "propagation extinction"); }
    float vx_prop_prev(int i) const { return prop_prev.at(i, "propagation slice"); }
    float vx_prop_in(int i) const { return prop_in.at(i, "sweep input"); }

#include "vx_march.h"
};
// The lighting methods' own kernel text compiles into structs derived from this one
// (CpuSatKernel, CpuPropagationKernel in their kernel/ folders).

}  // namespace voxlux::kernel

namespace voxlux {
// The kernel bound to the march inputs' arrays (the light-pass members S and sat stay unset).
kernel::CpuKernel bindCpuKernel(const KernelInputs& inputs);
}  // namespace voxlux
