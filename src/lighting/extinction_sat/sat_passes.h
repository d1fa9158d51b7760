// The Extinction-SAT method's passes on one device (Schlegel 2011): the SAT scan over the light
// grid and the light-cache channels, AO shells and shadow cones, queried from it. The CPU runs
// them with TBB (summed_volume.cpp, cpu_light_pass.cpp) and, for the light passes, the kernel's
// SIMD row batches, GL as the compute programs sat_scan.comp and light_cache.comp
// (gl_sat_passes.cpp); both give the same integers and, per cell, the same kernel arithmetic
// (src/lighting/extinction_sat/kernel/vx_sat.h).
#pragma once
#include <memory>

#include "kernel/kernel_backend.h"
#include "lighting/extinction_sat/light_pass.h"
#include "lighting/light_grid.h"
#include "lighting/extinction_sat/summed_volume.h"

namespace voxlux {

class SatPasses {
public:
    virtual ~SatPasses() = default;
    // The SAT of a light grid, reusing `sat`'s storage.
    virtual void buildSat(const LightGrid& grid, SummedVolume& sat) = 0;
    // One light-cache channel (see LightPass).
    virtual void fillLightChannel(const LightPass& pass, LightCache& cache) = 0;
};

std::unique_ptr<SatPasses> makeSatPasses(Device device);

}  // namespace voxlux
