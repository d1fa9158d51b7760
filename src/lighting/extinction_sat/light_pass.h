// One light pass of the Extinction-SAT method (Schlegel 2011, Sec. 3): which light-cache channel
// to fill from which SAT, for which cells. Either device runs it (sat_passes.h); its cost is one
// AO-shell or shadow-cone query per needed cell.
#pragma once
#include <cstdint>
#include <vector>

#include "kernel/kernel_types.h"
#include "lighting/extinction_sat/kernel/light_cache.h"

namespace voxlux {

struct SummedVolume;

// One light pass: fills channel params.channel of the cache from the SAT, for the cells `needed`
// marks. params.light is the light (index into `lights`), or -1 for ambient occlusion, which
// reads SAT plane params.ao_plane.
struct LightPass {
    kernel::VxSatParams params{};
    const std::vector<kernel::VxLight>* lights = nullptr;
    const SummedVolume* sat = nullptr;
    uint64_t sat_generation = 0;   // changes whenever the SAT's contents do (GL re-uploads then)
    const std::vector<uint8_t>* needed = nullptr;
};

}  // namespace voxlux
