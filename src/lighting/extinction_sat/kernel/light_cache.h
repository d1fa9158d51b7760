// The light cache (Schlegel 2011, Sec. 3): per light-grid cell, the optical depths the march
// turns into ambient occlusion and shadows, filled by SAT queries (src/lighting/extinction_sat/kernel/vx_sat.h) on either
// backend. Channels: ambient occlusion (1, or 3 with colour bleeding), then one per scene light
// (in packed order) when shadows are "sat_cone".
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_types.h"

namespace voxlux {

struct LightCache {
    glm::ivec3 dims{0};
    int channels = 0;
    int ambient_channel = -1;      // first AO channel, or -1
    int ambient_width = 1;         // 3 with colour bleeding
    int shadow_channel = -1;       // channel of packed light 0, or -1
    glm::mat4 world_to_cache{1.0f};
    std::vector<float> values;     // cell-major: channels floats per cell
};

}  // namespace voxlux
