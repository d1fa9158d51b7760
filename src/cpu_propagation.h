// CPU backend of a propagation sweep: the shared kernel (shaders/vx_propagation.h) slice after
// slice, each slice's rows in parallel (TBB), with two 2D slice buffers (read the previous, write
// the current), as Sunden 2015 keeps them.
#pragma once
#include "illumination_volume.h"

namespace voxlux {

void propagateCpu(const SweepJob& job, IlluminationVolume& volume);

}  // namespace voxlux
