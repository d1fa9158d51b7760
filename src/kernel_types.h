// The shared kernel's data types (shaders/vx_types.h) seen from C++.
#pragma once
#include <glm/glm.hpp>

namespace voxlux::kernel {
using namespace glm;
using uint = unsigned int;
#include "vx_types.h"
static_assert(sizeof(VxParams) == 4 * 64 + 19 * 16, "VxParams must match the std430 layout");
static_assert(VX_MAX_EMISSION == 4, "VxParams::emission_domain holds one source per vec4 component");
static_assert(sizeof(VxSatParams) == 2 * 64 + 5 * 16, "VxSatParams must match the std140 layout");
static_assert(sizeof(VxPropParams) == 2 * 64 + 8 * 16 + 48 + VX_MAX_TAPS * 16, "VxPropParams must match the std140 layout");
static_assert(sizeof(VxLight) == 48, "VxLight must match the std430 layout");
}  // namespace voxlux::kernel
