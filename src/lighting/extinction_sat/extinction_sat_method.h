// Extinction-SAT lighting (Schlegel 2011) registered as a lighting method (lighting_method.h).
#pragma once
#include <memory>

#include "lighting/lighting_method.h"

namespace voxlux {

std::unique_ptr<LightingMethod> makeExtinctionSatMethod(const SharedStages& shared);

}  // namespace voxlux
