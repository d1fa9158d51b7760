// Illumination propagation (Ropinski 2010, Sunden 2015) registered as a lighting method
// (lighting_method.h).
#pragma once
#include <memory>

#include "lighting/lighting_method.h"

namespace voxlux {

std::unique_ptr<LightingMethod> makePropagationMethod(const SharedStages& shared);

}  // namespace voxlux
