// What the propagation's tests share about the illumination volume's cells.
#pragma once
#include <glm/glm.hpp>

#include "lighting/propagation/kernel/illumination_volume.h"

namespace voxlux::test {

// World centre of cell c.
inline glm::vec3 cellCentre(const IlluminationVolume& v, glm::ivec3 c) {
    return glm::vec3(glm::inverse(v.world_to_illum) * glm::vec4(glm::vec3(c) + 0.5f, 1.0f));
}

}  // namespace voxlux::test
