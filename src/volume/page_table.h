// Classify stage: decide which bricks the material makes visible and build the page table (an
// open-addressed hash from brick coordinate to atlas slot) over only those. Empty bricks are
// absent, so the march skips them without reading the atlas, and regions without any brick in
// one step. Cost: linear in the atlas's bricks.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "volume/brick_atlas.h"
#include "scene/scene.h"

namespace voxlux {

// The bricks' table, then the regions' (the march's coarse level, shaders/vx_dda.h): which regions
// of VX_REGION_BRICKS^3 bricks hold any brick, so a ray crosses an empty one in one step. Both are
// open-addressed tables sized by what they hold, never by the bounding box.
struct PageTable {
    // The brick_capacity entries (brick x, y, z, slot) of the bricks, then the region_capacity
    // entries (region x, y, z, bricks in it); VX_PAGE_EMPTY in w marks a free entry.
    std::vector<glm::ivec4> entries;
    int brick_capacity = 0;
    int max_probe = 0;                 // longest probe sequence of any stored brick
    int region_capacity = 0;           // 0: no table (most regions of the box hold bricks)
    int region_max_probe = 0;
    glm::ivec3 bricks_min{0}, bricks_max{-1};
    // The box of the bricks the medium occupies in the frame, without the bricks motion blur adds
    // around it: the light grids' box (the march reads them only where the medium was).
    glm::ivec3 medium_min{0}, medium_max{-1};
    size_t occupied = 0;
    bool empty() const { return occupied == 0; }
};

// True for bricks the material gives non-zero extinction somewhere, or that some emission source
// (one per atlas emission channel) makes emit.
std::vector<char> classifyBricks(const BrickAtlas& atlas, const Material& material,
                                 const std::vector<EmissionSource>& emission);

// The page table of `scene` over `atlas`. It holds classifyBricks, under motion blur the stored
// bricks within the atlas's motion_reach of those, and under the tricubic filter the
// stored neighbours (of the 26 around) of every visible brick too. That filter reads them and
// must find their real values (colour, density a transfer function makes transparent), not the 0
// of a brick missing from the page table. Its medium box (PageTable::medium_min) leaves out the
// motion reach.
PageTable classifiedPageTable(const BrickAtlas& atlas, const Scene& scene);
// The same for `volume` of a scene rendered with `filter`.
PageTable classifiedPageTable(const BrickAtlas& atlas, const VolumeSpec& volume, Filter filter);

PageTable buildPageTable(const std::vector<glm::ivec3>& coords, const std::vector<char>& visible);

}  // namespace voxlux
