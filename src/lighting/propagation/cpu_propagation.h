// CPU backend of a propagation pass: the shared kernel (src/lighting/propagation/kernel/vx_propagation.h) slice after
// slice, each slice's rows in parallel (TBB). Every light of the pass has its own two 2D slice
// buffers (read the previous, write the current) and all of them add into the volume's slice
// together, as Sunden 2015's coherence-based propagation does: one walk over the extinction and
// the volume per pass, however many lights it carries.
#pragma once
#include "lighting/propagation/propagation_pass.h"

namespace voxlux {

void propagateCpu(const PropagationPass& pass, IlluminationVolume& volume);

}  // namespace voxlux
