// Which 8^3 bricks a grid's active values occupy: leaf nodes plus active tiles expanded to
// brick size (clouds store constant interiors as tiles; dropping them leaves holes).
#pragma once
#include <vector>

#include <glm/glm.hpp>
#include <openvdb/openvdb.h>

#include "core/error.h"

namespace voxlux {

// Upper bound on bricks in one volume (4M bricks = 11 GiB of float density): past it we refuse
// rather than exhaust memory on a hostile or mis-scaled file.
constexpr size_t kMaxBricks = size_t(1) << 22;

inline glm::ivec3 brickOf(const openvdb::Coord& c) { return {c.x() >> 3, c.y() >> 3, c.z() >> 3}; }

// Appends the bricks of `tree` to `out` (unsorted, may repeat across calls).
template <typename TreeT>
void collectBricks(const TreeT& tree, std::vector<glm::ivec3>& out, const std::string& what) {
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
        if (leaf->onVoxelCount() > 0) out.push_back(brickOf(leaf->origin()));
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        if (!it.isTileValue()) continue;
        openvdb::CoordBBox box = it.getBoundingBox();
        glm::ivec3 lo = brickOf(box.min()), hi = brickOf(box.max());
        size_t n = size_t(hi.x - lo.x + 1) * size_t(hi.y - lo.y + 1) * size_t(hi.z - lo.z + 1);
        if (out.size() + n > kMaxBricks)
            throw InputError(what + ": active tiles expand to more than " + std::to_string(kMaxBricks) +
                             " bricks of 8^3 voxels; refusing to densify");
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) out.push_back({x, y, z});
    }
}

// Offset n in [0, 27) of the 3x3x3 block of bricks around one (n = 13 is the brick itself): the
// bricks the tricubic filter's taps can reach.
inline glm::ivec3 brickNeighbourOffset(int n) { return {n % 3 - 1, n / 3 % 3 - 1, n / 9 - 1}; }

// z-major order, which keeps neighbouring bricks close in the atlas.
inline bool brickLess(const glm::ivec3& a, const glm::ivec3& b) {
    return a.z != b.z ? a.z < b.z : a.y != b.y ? a.y < b.y : a.x < b.x;
}

// For each of `bricks`, whether some brick of `sources` lies within `reach` bricks of it along
// every axis. Cost: one hash of `sources`, and per brick the sources in the 27 buckets of
// (reach + 1)^3 bricks around it.
std::vector<char> bricksWithinReach(const std::vector<glm::ivec3>& bricks, const std::vector<glm::ivec3>& sources, int reach);

// Sorts (brickLess) and removes repeats.
void uniqueBricks(std::vector<glm::ivec3>& bricks);

// Number of distinct bricks a grid of any type occupies (for `voxlux info`).
size_t countBricks(const openvdb::GridBase& grid);

}  // namespace voxlux
