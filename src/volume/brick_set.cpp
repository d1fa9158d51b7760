#include "volume/brick_set.h"

#include <algorithm>
#include <unordered_map>

namespace voxlux {

void uniqueBricks(std::vector<glm::ivec3>& b) {
    std::sort(b.begin(), b.end(), brickLess);
    b.erase(std::unique(b.begin(), b.end()), b.end());
}

std::vector<char> bricksWithinReach(const std::vector<glm::ivec3>& bricks, const std::vector<glm::ivec3>& sources, int reach) {
    // Buckets of (reach + 1)^3 bricks: a source within reach lies in one of the 27 around a brick's.
    const int size = reach + 1;
    const auto bucket = [size](const glm::ivec3& b) {
        const glm::ivec3 c(b.x >= 0 ? b.x / size : -((-b.x + size - 1) / size), b.y >= 0 ? b.y / size : -((-b.y + size - 1) / size),
                           b.z >= 0 ? b.z / size : -((-b.z + size - 1) / size));
        return (uint64_t(uint32_t(c.x) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y) & 0x1fffff) << 21) | uint64_t(uint32_t(c.z) & 0x1fffff);
    };
    std::unordered_map<uint64_t, std::vector<glm::ivec3>> buckets;
    for (const auto& s : sources) buckets[bucket(s)].push_back(s);
    std::vector<char> out(bricks.size(), 0);
    for (size_t i = 0; i < bricks.size(); ++i) {
        for (int n = 0; n < 27 && !out[i]; ++n) {
            const auto it = buckets.find(bucket(bricks[i] + brickNeighbourOffset(n) * size));
            if (it == buckets.end()) continue;
            for (const auto& s : it->second) {
                const glm::ivec3 gap = glm::abs(s - bricks[i]);
                if (std::max(gap.x, std::max(gap.y, gap.z)) <= reach) {
                    out[i] = 1;
                    break;
                }
            }
        }
    }
    return out;
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
