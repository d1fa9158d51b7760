// The perturbation's noise table (Kniss 2003, Sec. III.D): VX_NOISE_SIZE^3 texels of four random
// components in [-1, 1], drawn from a seeded generator and blurred slightly (wrapping) so that
// trilinear reads of the tiling table show no texel grid. The same seed gives the same table on
// every machine.
#pragma once
#include <vector>

#include <glm/glm.hpp>

namespace voxlux {

std::vector<glm::vec4> makeNoiseTable(int seed);

}  // namespace voxlux
