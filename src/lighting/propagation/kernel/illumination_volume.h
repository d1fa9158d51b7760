// The illumination volume (Ropinski 2010, Sunden 2015): per cell of a dense grid over the occupied
// bricks, the direct RGB radiance that reaches it through the medium from all lights together
// and, with indirect light, the blurred, transport-attenuated RGB radiance (Kniss 2003), possibly
// on a grid coarser by the chroma subsampling factor. Every light sweep adds its weighted light,
// so any number of lights and both blend axes share one volume, and a light is taken out again by
// sweeping it with a negative weight. With light groups (output.aovs "light_groups") or light
// linking, each group and link set has a volume of its own (a block), one after another, and the
// march reads its own (vx_light_block).
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_types.h"

namespace voxlux {

struct IlluminationVolume {
    glm::ivec3 dims{0};             // direct cells
    int chroma = 1;                 // chroma subsampling factor: indirect cells are chroma^3 direct cells
    glm::ivec3 chroma_dims{0};      // indirect cells (0 without indirect light)
    glm::mat4 world_to_illum{1.0f}; // world -> direct-cell coordinates
    int blocks = 1;                 // light groups (Scene lightGroupMarches) times link sets: one such volume each
    std::vector<float> values;      // per block: RGB per direct cell, then RGB per indirect cell

    size_t cells() const { return size_t(dims.x) * dims.y * dims.z; }
    size_t chromaCells() const { return size_t(chroma_dims.x) * chroma_dims.y * chroma_dims.z; }
    size_t indirectOffset() const { return 3 * cells(); }   // within a block
    size_t blockFloats() const { return 3 * cells() + 3 * chromaCells(); }
};

}  // namespace voxlux
