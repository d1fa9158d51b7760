// Colour of a blackbody emitter from first principles: Planck's law integrated against the CIE 1931
// colour-matching functions, so emission temperatures give the same colour as any colorimetry tool.
#pragma once
#include <glm/glm.hpp>

namespace voxlux {

// CIE 1931 XYZ (2 degree observer) of a blackbody's spectral radiance at `kelvin`: Planck's law
// integrated against the CIE colour-matching functions over 360..830 nm. Absolute scale: Y is
// proportional to luminance (units W sr^-1 m^-2 weighted by ybar, i.e. luminance / 683 lm/W).
// kelvin <= 0 gives 0.
glm::dvec3 blackbodyXYZ(double kelvin);

// CIE xy chromaticity of the above (kelvin > 0).
glm::dvec2 blackbodyChromaticity(double kelvin);

// The CIE 1931 2 degree colour-matching functions (xbar, ybar, zbar) at `nanometres`, linearly
// interpolated between the 5 nm table the integrals above use; 0 outside 360..830 nm. Public so
// tests can integrate the same data independently of the blackbody code.
glm::dvec3 cieColourMatching(double nanometres);

}  // namespace voxlux
