// How far one render is from another: the error measures of `voxlux study` (docs/accuracy.md).
// Both images are premultiplied scene-linear RGB in the same working space, over black.
#pragma once
#include <glm/glm.hpp>

#include "kernel/kernel_backend.h"

namespace voxlux {

// Mean squared difference of R, G and B over all pixels. The images must have the same size.
double meanSquaredError(const RenderImage& a, const RenderImage& b);

// The mean squared error of the average of two independent half renders `a` and `b` against the
// noise-free image, estimated from their difference: E[(a - b)^2] / 4 (both halves unbiased with
// equal variance). What a noisy ground truth adds to every MSE measured against it.
double halvesNoiseMse(const RenderImage& a, const RenderImage& b);

// The two half renders' mean (RGBA; the AOVs are a's): the image a render of both halves' samples
// would give.
RenderImage meanOfHalves(const RenderImage& a, const RenderImage& b);

// Mean over pixels of ITU-R BT.2124 Delta E_ITP, an HDR colour difference in which 1 is about
// one just-noticeable difference. `working_to_xyz` takes the working space to CIE XYZ (D65);
// scene-linear 1.0 is shown at `white_nits` cd/m^2. Negative components count as 0.
double meanDeltaEItp(const RenderImage& a, const RenderImage& b, const glm::mat3& working_to_xyz,
                     double white_nits = 100.0);

}  // namespace voxlux
