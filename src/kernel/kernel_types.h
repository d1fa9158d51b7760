// The shared kernel's data types (shaders/vx_types.h) seen from C++.
#pragma once
#include <cstddef>

#include <glm/glm.hpp>

namespace voxlux::kernel {
using namespace glm;
using uint = unsigned int;
#include "vx_types.h"
// std140 and C++ agree when every vector, matrix and struct member sits at a multiple of 16 bytes
// and every struct is whole 16-byte lines (vx_types.h).
#define VX_LINE_ALIGNED(T, member) static_assert(offsetof(T, member) % 16 == 0, #T "::" #member " must start a 16-byte line")
static_assert(sizeof(VxLight) == 48);
VX_LINE_ALIGNED(VxLight, position);
VX_LINE_ALIGNED(VxLight, direction);
VX_LINE_ALIGNED(VxLight, color);
static_assert(sizeof(VxParams) % 16 == 0);
VX_LINE_ALIGNED(VxParams, camera_to_world);
VX_LINE_ALIGNED(VxParams, world_to_index);
VX_LINE_ALIGNED(VxParams, world_to_cache);
VX_LINE_ALIGNED(VxParams, world_to_illum);
VX_LINE_ALIGNED(VxParams, albedo);
VX_LINE_ALIGNED(VxParams, bricks_min);
VX_LINE_ALIGNED(VxParams, bricks_max);
VX_LINE_ALIGNED(VxParams, ambient);
VX_LINE_ALIGNED(VxParams, emission_domain);
VX_LINE_ALIGNED(VxParams, cache_dims);
VX_LINE_ALIGNED(VxParams, illum_dims);
VX_LINE_ALIGNED(VxParams, chroma_dims);
VX_LINE_ALIGNED(VxParams, noise_offset);
VX_LINE_ALIGNED(VxParams, use_velocity);
VX_LINE_ALIGNED(VxParams, use_surface_grid);
VX_LINE_ALIGNED(VxParams, camera_open);
VX_LINE_ALIGNED(VxParams, camera_close);
static_assert(VX_MAX_EMISSION == 4, "VxParams::emission_domain holds one source per vec4 component");
static_assert(sizeof(VxSatParams) % 16 == 0);
VX_LINE_ALIGNED(VxSatParams, light_to_world);
VX_LINE_ALIGNED(VxSatParams, world_to_light);
VX_LINE_ALIGNED(VxSatParams, dims);
VX_LINE_ALIGNED(VxSatParams, quantum);
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
#undef VX_LINE_ALIGNED
}  // namespace voxlux::kernel
