// Median-cut sampling of an environment map (Debevec 2005): the map split into K regions of about
// equal power, each region's light given to one directional light at its power centroid. A region
// splits across its longer side (as angles: the width at its middle latitude) where the power on
// either side is equal; the region of the most power splits next, so any K works and a sun takes
// lights before a dim sky does. With a floor, the map's darkest value per channel becomes a uniform
// ambient remainder and the K lights carry the rest, so a constant map is all ambient. Costs one
// pass over a region's pixels per split: O(pixels x log K).
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "optics/environment_map.h"

namespace voxlux {

struct CutLight {
    glm::vec3 toward{0.0f, 0.0f, 1.0f};   // unit world direction from the scene to the light
    glm::vec3 irradiance{0.0f};           // its region's radiance above the floor times solid angle
    glm::ivec4 region{0};                 // its pixels: x0, y0, x1, y1 (ends exclusive)
};

struct MedianCut {
    std::vector<CutLight> lights;         // at most K, fewer when the map has fewer pixels
    glm::vec3 ambient{0.0f};              // the floor's radiance (0 without one)
};

// K >= 0 lights; K = 0 leaves everything above the floor out. `floor`: the per-channel minimum of
// the map becomes the ambient remainder.
MedianCut medianCut(const EnvironmentMap& map, int lights, bool floor);

}  // namespace voxlux
