// GL side of the kernel's data: the parameters and the accessor functions that vx_sample.h,
// vx_optics.h and vx_march.h call, read from buffers the GL backend (src/gl_backend.cpp) binds by
// block name. Assembled right after vx_types.h, so everything is declared before the kernel uses it.
// Every array is std430: float arrays are tightly packed, vec4/ivec4/VxLight match the C++ bytes.

layout(std140, binding = 0) uniform Params { VxParams P; };  // all mat4/vec4/ivec4: std140 == C++ layout
layout(std140, binding = 1) uniform SatParams { VxSatParams S; };  // light passes only
layout(std140, binding = 2) uniform PropParams { VxPropParams Q; };  // propagation sweeps only

layout(std430, binding = 0) readonly buffer AtlasDensity { float vx_density_data[]; };
layout(std430, binding = 1) readonly buffer AtlasEmission { float vx_emission_data[]; };
layout(std430, binding = 2) readonly buffer AtlasColor { float vx_color_data[]; };   // 3 floats per voxel
layout(std430, binding = 3) readonly buffer PageTable { ivec4 vx_page_data[]; };
layout(std430, binding = 4) readonly buffer Lights { VxLight vx_light_data[]; };
layout(std430, binding = 5) readonly buffer TransferLut { vec4 vx_tf_data[]; };
layout(std430, binding = 7) readonly buffer LightCache { float vx_cache_data[]; };
layout(std430, binding = 8) readonly buffer Sat { uint vx_sat_data[]; };     // 3 words per entry
layout(std430, binding = 11) readonly buffer Illumination { float vx_illum_data[]; };
layout(std430, binding = 12) readonly buffer Noise { vec4 vx_noise_data[]; };
layout(std430, binding = 13) readonly buffer PropSigma { float vx_prop_sigma_data[]; };
layout(std430, binding = 14) readonly buffer SliceIn { float vx_prop_prev_data[]; };
layout(std430, binding = 17) readonly buffer EyeInput { float vx_prop_in_data[]; };
layout(std430, binding = 18) readonly buffer EmissionLut { vec4 vx_emission_lut_data[]; };

float vx_atlas_density(int i) { return vx_density_data[i]; }
float vx_atlas_emission(int i) { return vx_emission_data[i]; }
vec3 vx_atlas_color(int i) { return vec3(vx_color_data[3 * i], vx_color_data[3 * i + 1], vx_color_data[3 * i + 2]); }
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
