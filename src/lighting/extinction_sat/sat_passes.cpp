#include "lighting/extinction_sat/sat_passes.h"

#include "lighting/extinction_sat/cpu_light_pass.h"

namespace voxlux {

#if VOXLUX_HAS_GL
std::unique_ptr<SatPasses> makeGlSatPasses();   // gl_sat_passes.cpp
#endif

namespace {

class CpuSatPasses final : public SatPasses {
public:
    void buildSat(const LightGrid& grid, SummedVolume& sat) override { buildSummedVolume(grid, sat); }
    void fillLightChannel(const LightPass& pass, LightCache& cache) override { fillLightChannelCpu(pass, cache); }
};

}  // namespace

std::unique_ptr<SatPasses> makeSatPasses(Device device) {
#if VOXLUX_HAS_GL
    if (device == Device::Gl) return makeGlSatPasses();
#endif
    (void)device;
    return std::make_unique<CpuSatPasses>();
}

}  // namespace voxlux
