// Emission tables: what an emission source (scene.h) emits at each value of its grid, baked into
// the rows the kernel's vx_emission (shaders/vx_optics.h) interpolates.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

// CIE XYZ (D65 white) -> ACEScg (AP1 primaries, ACES white x 0.32168, y 0.33767; Academy
// S-2014-004), adapting D65 (x 0.3127, y 0.3290) to the ACES white with Bradford's cone matrix.
// Derived from those chromaticities; its AP1 -> XYZ half reproduces S-2014-004's matrix to 1e-10,
// and it is the inverse of OpenColorIO's built-in "ACES-AP1_to_CIE-XYZ-D65_BFD" (tested). The
// working space when no colour pipeline supplies its own.
inline const glm::mat3 kXyzD65ToAcescg = glm::transpose(glm::mat3(  // rows as written
    1.6605853265f, -0.3152955608f, -0.2415093276f,
    -0.6599260632f, 1.6083914696f, 0.0172985947f,
    0.0090025691f, -0.0035668764f, 0.9136433128f));

struct EmissionTable {
    // VX_EMISSION_LUT_SIZE rows: rgb = radiance per world unit (working space) at grid value
    // grid_max * i / (VX_EMISSION_LUT_SIZE - 1); w = 0.
    std::vector<glm::vec4> rows;
    // The largest grid value at which the interpolated table is still exactly 0: a brick whose
    // values stay at or below it emits nothing from this source. +inf when no row emits.
    float threshold = 0.0f;
};

// Radiance per world unit (working space) `source` emits at grid value `value`.
glm::vec3 emissionRadiance(const EmissionSource& source, float value, const glm::mat3& xyz_to_working);

// The table of `source` over grid values [0, grid_max] (the largest value of its grid in this
// frame). Blackbody colours go from XYZ to the working space through `xyz_to_working`.
EmissionTable bakeEmission(const EmissionSource& source, float grid_max, const glm::mat3& xyz_to_working);

}  // namespace voxlux
