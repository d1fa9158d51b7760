#include "lighting/propagation/propagation_passes.h"

#include "lighting/propagation/cpu_propagation.h"

namespace voxlux {

#if VOXLUX_HAS_GL
std::unique_ptr<PropagationPasses> makeGlPropagationPasses();   // gl_propagation_passes.cpp
#endif

namespace {

class CpuPropagationPasses final : public PropagationPasses {
public:
    void propagate(const PropagationPass& pass, IlluminationVolume& volume) override { propagateCpu(pass, volume, scratch_); }

private:
    CpuSweepScratch scratch_;
};

}  // namespace

std::unique_ptr<PropagationPasses> makePropagationPasses(Device device) {
#if VOXLUX_HAS_GL
    if (device == Device::Gl) return makeGlPropagationPasses();
#endif
    (void)device;
    return std::make_unique<CpuPropagationPasses>();
}

}  // namespace voxlux
