// GL side of the kernel's data that is not one array per accessor: the atlas's colour, velocity
// and surface weight, and the depth holdouts' depth per pixel, share one storage block (a compute
// program may have 16 on llvmpipe), and the
// volumes of a scene of several are a uniform block of VX_MAX_VOLUMES, which spares a storage
// block. Every other block and accessor is generated (vx_gl_data.glsl,
// cmake/kernel_contract.cmake), which this file follows in a program; the CPU keeps these as arrays
// of their own (cpu_kernel_data.h).

// The colour grid's 3 floats a voxel, then from P.velocity_offset the velocity's, then from
// P.surface_offset the surface weight's 1, then from P.holdout_offset a pixel's holdout depth.
layout(std430, binding = VX_BIND_ATLAS_VECTORS) readonly buffer AtlasVectors { float vx_vector_data[]; };

vec3 vx_atlas_color(int i) { return vec3(vx_vector_data[3 * i], vx_vector_data[3 * i + 1], vx_vector_data[3 * i + 2]); }
vec3 vx_atlas_velocity(int i) {
    int v = P.velocity_offset + 3 * i;
    return vec3(vx_vector_data[v], vx_vector_data[v + 1], vx_vector_data[v + 2]);
}
float vx_atlas_surface(int i) { return vx_vector_data[P.surface_offset + i]; }
float vx_holdout(int i) { return vx_vector_data[P.holdout_offset + i]; }

// The volumes of a scene of several (P.volume_count of them; shaders/vx_volumes.h).
layout(std140, binding = VX_BIND_VOLUMES) uniform Volumes { VxVolume vx_placed_volume_data[VX_MAX_VOLUMES]; };
VxVolume vx_placed_volume(int i) { return vx_placed_volume_data[i]; }
