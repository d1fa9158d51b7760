#include "volume/brick_set.h"

#include <algorithm>

namespace voxlux {

void uniqueBricks(std::vector<glm::ivec3>& b) {
    std::sort(b.begin(), b.end(), brickLess);
    b.erase(std::unique(b.begin(), b.end()), b.end());
}

size_t countBricks(const openvdb::GridBase& grid) {
    std::vector<glm::ivec3> bricks;
    bool known = grid.apply<openvdb::GridTypes>([&](const auto& g) {
        collectBricks(g.tree(), bricks, "grid '" + grid.getName() + "'");
    });
    if (!known) return 0;
    uniqueBricks(bricks);
    return bricks.size();
}

}  // namespace voxlux
