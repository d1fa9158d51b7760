// Which sweeps carry a light through the illumination volume (Ropinski 2010, Sec. 4.1-4.2), and
// the blur taps of the indirect sweep (Kniss 2003, Eq. 9). Pure geometry, no data.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_types.h"
#include "scene/scene.h"

namespace voxlux {

// One sweep: slices advance along `axis` in direction `sign`, and add `weight` times their light.
struct Sweep {
    int axis = 0;
    int sign = 1;
    float weight = 1.0f;
};

// The sweeps for light flowing along `flow` (grid space, any length; zero counts as +z). The
// principal axis is the one the flow is closest to (the face with the largest projection). With
// `blend`, the second closest axis is swept too, with the weights of vx_sweep_weight
// (src/lighting/propagation/kernel/vx_propagation.h): Sunden 2015's Eq. 5a/5b in the plane of two axes, continuous off it.
// Sweeps of zero weight are left out, so an axis-aligned light costs one sweep; the principal
// axis comes first.
std::vector<Sweep> sweepsFor(glm::vec3 flow, bool blend);

// The sweeps a point or spot light at grid position `at` needs over a grid of `dims` cells: every
// axis and direction for which some cell centre's own flow gives it a non-zero weight. A light
// far outside needs one or two, a light beside the volume or near a corner up to five, a light
// inside all six (Sunden 2015, Sec. 7.3). Their weight is 1: the kernel weights each cell.
std::vector<Sweep> pointLightSweeps(glm::vec3 at, glm::ivec3 dims, bool blend);

// Of `sweeps` (from pointLightSweeps, one axis: blend false), those a spot light can reach: its
// cone (world direction `direction`, outer half-angle whose cosine is `cos_outer`) meets the
// pyramid of flows the sweep weights. `world_to_grid` maps directions into the grid. A spot
// inside the volume pointing down needs one pass instead of six (Sunden 2015, Sec. 7.3).
std::vector<Sweep> spotLightSweeps(const std::vector<Sweep>& sweeps, glm::vec3 direction, float cos_outer,
                                   const glm::mat3& world_to_grid);

// Blur taps on the unit disc (xy) with weights (z) summing to 1: the centre (odd counts) and
// opposite pairs on a Vogel spiral, weighted by the Phong lobe cos^exponent or the
// Henyey-Greenstein phase of the angle between the light and the tap, for a cone of apex angle
// indirect.angle.
std::vector<kernel::VxTap> blurTaps(const Indirect& indirect);
std::vector<kernel::VxTap> directTaps();   // the direct sweep's single tap: no blur

}  // namespace voxlux
