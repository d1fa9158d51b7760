// The CPU backend's light passes (see cpu_light_pass.cpp).
#pragma once
#include "lighting/extinction_sat/light_pass.h"

namespace voxlux {

void fillLightChannelCpu(const LightPass& pass, LightCache& cache);

}  // namespace voxlux
