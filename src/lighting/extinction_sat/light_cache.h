// The light cache (Schlegel 2011, Sec. 3): per light-grid cell, the optical depths the march
// turns into ambient occlusion and shadows, filled by SAT queries (src/lighting/extinction_sat/vx_sat.h) on either
// backend. Channels: ambient occlusion (1, or 3 with colour bleeding), then one per scene light
// (in packed order) when shadows are "sat_cone".
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_types.h"

namespace voxlux {

struct SummedVolume;

struct LightCache {
    glm::ivec3 dims{0};
    int channels = 0;
    int ambient_channel = -1;      // first AO channel, or -1
    int ambient_width = 1;         // 3 with colour bleeding
    int shadow_channel = -1;       // channel of packed light 0, or -1
    glm::mat4 world_to_cache{1.0f};
    std::vector<float> values;     // cell-major: channels floats per cell
};

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
