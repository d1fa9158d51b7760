// Which sweeps carry a light through the illumination volume (Ropinski 2010, Sec. 4.1-4.2), and
// the blur taps of the indirect sweep (Kniss 2003, Eq. 9). Pure geometry, no data.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "kernel_types.h"
#include "scene.h"

namespace voxlux {

// One sweep: slices advance along `axis` in direction `sign`, and add `weight` times their light.
struct Sweep {
    int axis = 0;
    int sign = 1;
    float weight = 1.0f;
};

// The sweeps for light flowing along `flow` (grid space, any length). The principal axis is the
// one the flow is closest to (the face with the largest projection). With `blend`, the second
// closest axis is swept too and the two are weighted by the angles to them, theta_i:
//   w0 ~ theta_2 - theta_0,  w1 ~ theta_2 - theta_1,  w0 + w1 = 1.
// In the plane of two axes (theta_2 = 90 deg) this is Ropinski's alpha_0 = 1 - 2 theta_0 / pi; out of
// it the weights still change continuously when the second and third axes swap, where Ropinski's
// would jump. Sweeps of zero weight are left out, so an axis-aligned light costs one sweep.
std::vector<Sweep> sweepsFor(glm::vec3 flow, bool blend);

// Blur taps on the unit disc (xy) with weights (z) summing to 1: the centre (odd counts) and
// opposite pairs on a Vogel spiral, weighted by the Phong lobe cos^exponent or the
// Henyey-Greenstein phase of the angle between the light and the tap, for a cone of apex angle
// indirect.angle.
std::vector<glm::vec4> blurTaps(const Indirect& indirect);
std::vector<glm::vec4> directTaps();   // the direct sweep's single tap: no blur

}  // namespace voxlux
