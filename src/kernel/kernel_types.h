// The shared kernel's data types (shaders/vx_types.h) seen from C++.
#pragma once
#include <cstddef>

#include <glm/glm.hpp>

namespace voxlux::kernel {
using namespace glm;
using uint = unsigned int;
#include "vx_types.h"
#include "vx_lighting_types.h"   // generated: the lighting methods' blocks and VxLighting
// std140 and C++ agree when every vector, matrix and struct member sits at a multiple of 16 bytes
// and every struct is whole 16-byte lines (vx_types.h).
#define VX_LINE_ALIGNED(T, member) static_assert(offsetof(T, member) % 16 == 0, #T "::" #member " must start a 16-byte line")
static_assert(sizeof(VxLight) == 64);
VX_LINE_ALIGNED(VxLight, position);
VX_LINE_ALIGNED(VxLight, direction);
VX_LINE_ALIGNED(VxLight, color);
static_assert(sizeof(VxParams) % 16 == 0);
VX_LINE_ALIGNED(VxParams, camera_to_world);
VX_LINE_ALIGNED(VxParams, world_to_index);
VX_LINE_ALIGNED(VxParams, albedo);
VX_LINE_ALIGNED(VxParams, bricks_min);
VX_LINE_ALIGNED(VxParams, bricks_max);
VX_LINE_ALIGNED(VxParams, ambient);
VX_LINE_ALIGNED(VxParams, emission_domain);
VX_LINE_ALIGNED(VxParams, noise_offset);
VX_LINE_ALIGNED(VxParams, use_velocity);
VX_LINE_ALIGNED(VxParams, use_surface_grid);
VX_LINE_ALIGNED(VxParams, focus_distance);
VX_LINE_ALIGNED(VxParams, camera_open);
VX_LINE_ALIGNED(VxParams, camera_close);
static_assert(sizeof(VxPageRange) == 48);
static_assert(sizeof(VxVolume) == 192);
VX_LINE_ALIGNED(VxVolume, pages);
VX_LINE_ALIGNED(VxVolume, albedo);
VX_LINE_ALIGNED(VxVolume, transfer_lo);
VX_LINE_ALIGNED(VxVolume, emission_first);
static_assert(VX_MAX_EMISSION == 4, "VxParams::emission_domain holds one source per vec4 component");
static_assert(sizeof(VxLighting) % 16 == 0, "each lighting method's block is whole 16-byte lines");
// A method's own blocks are checked in its kernel/ folder (cpu_<method>_kernel.h).
}  // namespace voxlux::kernel
