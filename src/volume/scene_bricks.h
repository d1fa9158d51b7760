// Several volumes in one atlas (shaders/vx_volumes.h): every volume's bricks appended to one
// atlas and its page table to one array of page entries, each volume keeping its own range of
// both (kernel::VxPageRange), so the march reaches any volume's bricks through one set of arrays.
// An instance reuses its volume's range. Cost: one copy of the volumes' density, emission and
// colour bricks and page entries; no dense array over their union's box.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_types.h"
#include "volume/brick_atlas.h"
#include "volume/page_table.h"

namespace voxlux {

// Where one volume's channels besides the density sit in the joined atlas (kernel::VxVolume's
// emission_*, color_offset and velocity_offset): its emission sources in `emission`, numbered
// volume by volume over the scene, its colour in `color`, and its velocity in `velocity`, turned
// from the file's world units into its index voxels (each volume moves in its own index space).
struct VolumeChannels {
    int emission_first = 0;    // its first source's number
    int emission_count = 0;
    int emission_offset = 0;   // from a tap's index in the joined density to its first source's
    int emission_stride = 0;   // floats from one of its sources to the next
    bool color = false;        // whether it has a colour grid
    int color_offset = 0;      // from a tap's index in the joined density to its colour's
    bool velocity = false;     // whether it moves under motion blur
    int velocity_offset = 0;   // from a tap's index in the joined density to its velocity's
};

struct SceneBricks {
    BrickAtlas atlas;                            // the volumes' density bricks, slot ranges one after another,
                                                 // and their emission sources', colours' and velocities'
                                                 // blocks (not emission_max: emission_grid_max below)
    PageTable pages;                             // their brick tables one after another (no regions' table)
    std::vector<kernel::VxPageRange> ranges;     // each volume's pages
    std::vector<glm::mat4> index_to_world;       // each volume's file's
    std::vector<VolumeChannels> channels;        // each volume's emission and colour
    std::vector<float> emission_grid_max;        // each source's largest value, by its number
};

// Whether range `r` holds no brick (its volume has nothing visible).
bool isEmptyRange(const kernel::VxPageRange& r);

// Grows [lo, hi] by the box of range `r`'s bricks mapped by `index_to_space` (its 8 corners); an
// empty range adds nothing and gives false.
bool growByPageRange(const kernel::VxPageRange& r, const glm::mat4& index_to_space, glm::vec3& lo, glm::vec3& hi);

// The volumes of `atlases` (each with its page table in `pages`) in one atlas and entries array.
SceneBricks joinVolumeBricks(const std::vector<const BrickAtlas*>& atlases, const std::vector<const PageTable*>& pages);

}  // namespace voxlux
