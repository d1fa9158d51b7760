// Kniss, Kindlmann and Hansen's two-dimensional transfer function (TVCG 2002): a voxel's optical
// properties from its value and its gradient magnitude, so that materials sharing a value range
// (the skin and the brain's boundary in an MRI) and the boundaries between materials (high
// gradient) can be told apart. The regions are rectangles and triangles in that plane.
// Evaluated exactly per voxel (no table to quantise): a handful of comparisons per region.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

struct Classified {
    float extinction = 0.0f;   // multiplies material.density_scale
    glm::vec3 albedo{1.0f};    // multiplies material.albedo
    glm::vec3 transport{1.0f}; // e^-(extinction-weighted mean of -ln transport): the colour whose
                               // optical depth per channel is the regions' together (1: none)
    float surface = 1.0f;      // the extinction-weighted mean of the regions' surface weights (1: none)
};

// Whether the regions carry a transport colour, a surface weight: every region does, or none does
// (the scene reader checks it), so the first one says.
inline bool regionsCarryTransport(const std::vector<TransferRegion>& regions) { return !regions.empty() && regions.front().transport; }
inline bool regionsCarrySurface(const std::vector<TransferRegion>& regions) { return !regions.empty() && regions.front().surface; }

// A region's weight at (value, gradient magnitude): 0 outside, 1 inside, ramped over `fade`.
float regionWeight(const TransferRegion& region, glm::vec2 point);

// The regions together: extinctions add (weighted), and the albedo is the extinction-weighted mean
// of the regions' albedos (1 where nothing is selected); so are -ln of their transport colours and
// their surface weights.
Classified classify2d(const std::vector<TransferRegion>& regions, float value, float gradient);

}  // namespace voxlux
