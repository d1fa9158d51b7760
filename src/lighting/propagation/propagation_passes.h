// The propagation method's passes on one device (Ropinski 2010, Sundén 2015): sweeps of lights,
// slice by slice, through a grid of extinction into the illumination volume. The CPU runs them
// with TBB (cpu_propagation.cpp) through the kernel's SIMD row batches, GL as the compute program
// propagate.comp (gl_propagation_passes.cpp); per cell both run vx_prop_cell (all three in
// src/lighting/propagation/kernel/vx_propagation.h).
#pragma once
#include <memory>

#include "lighting/propagation/propagation_pass.h"
#include "kernel/kernel_backend.h"

namespace voxlux {

class PropagationPasses {
public:
    virtual ~PropagationPasses() = default;
    // One propagation pass (see PropagationPass) into `volume`.
    virtual void propagate(const PropagationPass& pass, IlluminationVolume& volume) = 0;
};

std::unique_ptr<PropagationPasses> makePropagationPasses(Device device);

}  // namespace voxlux
