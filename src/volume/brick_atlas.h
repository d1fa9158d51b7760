// Brick stage: densify the active region of the loaded grids into 8^3 bricks with a 1-voxel apron
// on the + side (9^3 stored), so trilinear filtering never leaves a brick. This is the GPU layout;
// the CPU backend reads the same arrays. Memory follows the active voxels, never the bounding box.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "volume/vdb_loader.h"

namespace voxlux {

// Voxels that were not usable as given and were replaced.
struct SanitizeCounts {
    uint64_t non_finite = 0;   // NaN or Inf, set to 0
    uint64_t negative = 0;     // below 0, set to 0
    uint64_t above_one = 0;    // colour components above 1, set to 1
    bool any() const { return non_finite + negative + above_one > 0; }
};

struct BrickAtlas {
    glm::mat4 index_to_world{1.0f};
    std::vector<glm::ivec3> coords;          // brick coordinate (voxel >> 3) of each slot
    std::vector<float> density;              // slot * 729 + offset
    // One channel per emission source, source-major: (source * slots + slot) * 729 + offset.
    std::vector<float> emission;
    std::vector<float> color;                // empty, or 3 floats per voxel
    std::vector<float> transport;            // empty, or 3 floats per voxel: the transport colour
                                             // (LoadedVolume::transport), which light grids filter
    std::vector<float> surface;              // empty, or 1 float per voxel: the surface weight
    std::vector<float> velocity;             // empty, or 3 floats per voxel (world units per second)
    std::vector<glm::vec2> density_range;    // min and max over each slot's 9^3 block
    std::vector<float> emission_max;         // max over each 9^3 block: source * slots + slot
    size_t emission_sources = 0;
    SanitizeCounts density_fixes, color_fixes, velocity_fixes;
    std::vector<SanitizeCounts> emission_fixes;  // one per source
    uint64_t active_voxels = 0;              // of the density grid
    int motion_reach = 0;                    // bricks the blurred medium can move (motionReachBricks)

    size_t slots() const { return coords.size(); }
    float emissionGridMax(size_t source) const;  // the largest value of a source's grid (0 if no slots)
    size_t bytes() const;
};

// With `motion_reach` > 0 (motionReachBricks) it also stores the velocity grid's bricks within
// that many bricks of the medium: where the blurred medium can be seen (vx_motion.h).
BrickAtlas buildBrickAtlas(const LoadedVolume& volume, int motion_reach = 0);

// Human-readable lines for the counts above (empty when nothing was replaced).
std::vector<std::string> sanitizeReport(const BrickAtlas& atlas, const LoadedVolume& volume);

}  // namespace voxlux
