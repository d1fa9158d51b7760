// GL side of the kernel's data: the parameters and the accessor functions that vx_sample.h,
// vx_optics.h and vx_march.h call, read from buffers the GL backend (src/backend/gl/gl_backend.cpp) binds by
// block name. Assembled right after vx_types.h, so everything is declared before the kernel uses it.
// Every array is std430: float arrays are tightly packed, vec4/ivec4/VxLight match the C++ bytes.

layout(std140, binding = VX_BIND_PARAMS) uniform Params { VxParams P; };  // all mat4/vec4/ivec4: std140 == C++ layout
layout(std140, binding = VX_BIND_SAT_PARAMS) uniform SatParams { VxSatParams S; };  // light passes only
layout(std140, binding = VX_BIND_PROP_PARAMS) uniform PropParams { VxPropParams Q; };  // propagation sweeps only

layout(std430, binding = VX_BIND_ATLAS_DENSITY) readonly buffer AtlasDensity { float vx_density_data[]; };
layout(std430, binding = VX_BIND_ATLAS_EMISSION) readonly buffer AtlasEmission { float vx_emission_data[]; };
// The colour grid's 3 floats a voxel, then from P.velocity_offset the velocity's, then from
// P.surface_offset the surface weight's 1 (one block: a compute program may have 16).
layout(std430, binding = VX_BIND_ATLAS_VECTORS) readonly buffer AtlasVectors { float vx_vector_data[]; };
layout(std430, binding = VX_BIND_PAGE_TABLE) readonly buffer PageTable { ivec4 vx_page_data[]; };
layout(std430, binding = VX_BIND_LIGHTS) readonly buffer Lights { VxLight vx_light_data[]; };
layout(std430, binding = VX_BIND_TRANSFER_LUT) readonly buffer TransferLut { vec4 vx_tf_data[]; };
layout(std430, binding = VX_BIND_LIGHT_CACHE) readonly buffer LightCache { float vx_cache_data[]; };
layout(std430, binding = VX_BIND_SAT) readonly buffer Sat { uint vx_sat_data[]; };     // 3 words per entry
layout(std430, binding = VX_BIND_ILLUMINATION) readonly buffer Illumination { float vx_illum_data[]; };
layout(std430, binding = VX_BIND_NOISE) readonly buffer Noise { vec4 vx_noise_data[]; };
layout(std430, binding = VX_BIND_PROP_SIGMA) readonly buffer PropSigma { float vx_prop_sigma_data[]; };
layout(std430, binding = VX_BIND_SLICE_IN) readonly buffer SliceIn { float vx_prop_prev_data[]; };
layout(std430, binding = VX_BIND_SWEEP_INPUT) readonly buffer SweepInput { float vx_prop_in_data[]; };
layout(std430, binding = VX_BIND_EMISSION_LUT) readonly buffer EmissionLut { vec4 vx_emission_lut_data[]; };

float vx_atlas_density(int i) { return vx_density_data[i]; }
float vx_atlas_emission(int i) { return vx_emission_data[i]; }
vec3 vx_atlas_color(int i) { return vec3(vx_vector_data[3 * i], vx_vector_data[3 * i + 1], vx_vector_data[3 * i + 2]); }
vec3 vx_atlas_velocity(int i) {
    int v = P.velocity_offset + 3 * i;
    return vec3(vx_vector_data[v], vx_vector_data[v + 1], vx_vector_data[v + 2]);
}
float vx_atlas_surface(int i) { return vx_vector_data[P.surface_offset + i]; }
ivec4 vx_page_entry(int i) { return vx_page_data[i]; }
VxLight vx_light(int i) { return vx_light_data[i]; }
vec4 vx_tf_lut(int i) { return vx_tf_data[i]; }
vec4 vx_emission_lut(int i) { return vx_emission_lut_data[i]; }
float vx_cache(int i) { return vx_cache_data[i]; }
uint vx_sat_word(int i) { return vx_sat_data[i]; }
float vx_illum(int i) { return vx_illum_data[i]; }
vec4 vx_noise(int i) { return vx_noise_data[i]; }
float vx_prop_sigma(int i) { return vx_prop_sigma_data[i]; }
float vx_prop_prev(int i) { return vx_prop_prev_data[i]; }
float vx_prop_in(int i) { return vx_prop_in_data[i]; }
