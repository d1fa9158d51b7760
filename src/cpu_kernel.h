// The shared march kernel (shaders/vx_*.h) compiled as C++: the headers are included inside this
// struct, so their functions become members and the backend data accessors below are in scope,
// exactly as the GL backend provides them as buffer reads (shaders/march.comp).
#pragma once
#include "kernel_inputs.h"
#include "kernel_types.h"

namespace voxlux::kernel {

struct CpuKernel {
    VxParams P{};
    const float* density = nullptr;
    const float* emission = nullptr;       // source-major channels (P.emission_map)
    const float* color = nullptr;          // 3 floats per voxel
    const ivec4* page = nullptr;
    const VxLight* lights = nullptr;
    const vec4* tf_lut = nullptr;
    const vec4* emission_lut = nullptr;    // VX_EMISSION_LUT_SIZE rows per emission source
    const float* cache = nullptr;          // light cache, P.cache_dims.w floats per cell
    VxSatParams S{};                       // light passes only
    const uint* sat = nullptr;
    const float* illum = nullptr;          // illumination volume (march)
    const vec4* noise = nullptr;           // perturbation table
    VxPropParams Q{};                      // propagation sweeps only
    const float* prop_sigma = nullptr;
    const float* prop_prev = nullptr;
    const float* prop_in = nullptr;

    float vx_atlas_density(int i) const { return density[i]; }
    float vx_atlas_emission(int i) const { return emission[i]; }
    vec3 vx_atlas_color(int i) const { return vec3(color[3 * i], color[3 * i + 1], color[3 * i + 2]); }
    ivec4 vx_page_entry(int i) const { return page[i]; }
    VxLight vx_light(int i) const { return lights[i]; }
    vec4 vx_tf_lut(int i) const { return tf_lut[i]; }
    vec4 vx_emission_lut(int i) const { return emission_lut[i]; }
    float vx_cache(int i) const { return cache[i]; }
    uint vx_sat_word(int i) const { return sat[i]; }
    float vx_illum(int i) const { return illum[i]; }
    vec4 vx_noise(int i) const { return noise[i]; }
    float vx_prop_sigma(int i) const { return prop_sigma[i]; }
    float vx_prop_prev(int i) const { return prop_prev[i]; }
    float vx_prop_in(int i) const { return prop_in[i]; }

#include "vx_march.h"
#include "vx_sat.h"
#include "vx_propagation.h"
};

}  // namespace voxlux::kernel

namespace voxlux {
// The kernel bound to the march inputs' arrays (the light-pass members S and sat stay unset).
kernel::CpuKernel bindCpuKernel(const KernelInputs& inputs);
}  // namespace voxlux
