#include "volume/page_table.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "kernel/kernel_types.h"
#include "volume/brick_set.h"
#include "optics/emission.h"
#include "optics/transfer_function.h"

namespace voxlux {

std::vector<char> classifyBricks(const BrickAtlas& atlas, const Material& material,
                                 const std::vector<EmissionSource>& emission) {
    const size_t slots = atlas.slots();
    std::vector<char> visible(slots);
    const std::vector<glm::vec4> table = bakeTransfer(material.transfer);  // the kernel's own table
    for (size_t i = 0; i < slots; ++i) {
        const glm::vec2 r = atlas.density_range[i];
        float extinction =
            material.transfer.empty() ? r.y : maxTransferExtinction(table, material.transfer, r.x, r.y);
        visible[i] = extinction * material.density_scale > 0.0f;
    }
    // A brick emits when its largest value passes the value up to which the source's own table
    // (the kernel's) is zero. Which values emit does not depend on the working space.
    for (size_t e = 0; e < atlas.emission_sources; ++e) {
        const float* block_max = atlas.emission_max.data() + e * slots;
        const float threshold = bakeEmission(emission.at(e), atlas.emissionGridMax(e), kXyzD65ToAcescg).threshold;
        for (size_t i = 0; i < slots; ++i) visible[i] |= block_max[i] > threshold;
    }
    return visible;
}

namespace {

// `visible` with every stored neighbour of a visible brick added; `coords` sorted (brickLess), as
// the atlas keeps them.
std::vector<char> withNeighbours(const std::vector<glm::ivec3>& coords, const std::vector<char>& visible) {
    std::vector<char> out = visible;
    for (size_t i = 0; i < coords.size(); ++i) {
        if (!visible[i]) continue;
        for (int n = 0; n < 27; ++n) {
            const glm::ivec3 c = coords[i] + brickNeighbourOffset(n);
            const auto it = std::lower_bound(coords.begin(), coords.end(), c, brickLess);
            if (it != coords.end() && *it == c) out[size_t(it - coords.begin())] = 1;
        }
    }
    return out;
}

// `visible` with every stored brick within `reach` bricks of a visible one added: under motion
// blur, where the moving medium can be seen (the atlas stores velocity there).
std::vector<char> withinMotionReach(const std::vector<glm::ivec3>& coords, const std::vector<char>& visible, int reach) {
    std::vector<glm::ivec3> sources;
    for (size_t i = 0; i < coords.size(); ++i)
        if (visible[i]) sources.push_back(coords[i]);
    std::vector<char> out = bricksWithinReach(coords, sources, reach);
    for (size_t i = 0; i < out.size(); ++i) out[i] |= visible[i];
    return out;
}

// The box of the flagged bricks (lo > hi when none is).
void flaggedBox(const std::vector<glm::ivec3>& coords, const std::vector<char>& flags, glm::ivec3& lo, glm::ivec3& hi) {
    lo = glm::ivec3(INT32_MAX);
    hi = glm::ivec3(INT32_MIN);
    for (size_t i = 0; i < coords.size(); ++i)
        if (flags[i]) lo = glm::min(lo, coords[i]), hi = glm::max(hi, coords[i]);
}

// An open-addressed table of `keys` (value: their `values`) appended to `entries`: a power of two
// of at least twice the keys, probed linearly from the kernel's own hash, so lookups agree.
// Returns the table's capacity and sets its longest probe sequence.
int appendTable(std::vector<glm::ivec4>& entries, const std::vector<glm::ivec4>& keyed, int& max_probe) {
    size_t capacity = 16;
    while (capacity < 2 * keyed.size()) capacity *= 2;
    const size_t first = entries.size();
    entries.resize(first + capacity, glm::ivec4(0, 0, 0, VX_PAGE_EMPTY));
    const uint32_t mask = uint32_t(capacity - 1);
    max_probe = 0;
    for (const glm::ivec4& e : keyed) {
        uint32_t h = kernel::vx_brick_hash(glm::ivec3(e)) & mask;
        int probe = 0;
        while (entries[first + h].w != VX_PAGE_EMPTY) {
            h = (h + 1) & mask;
            ++probe;
        }
        entries[first + h] = e;
        max_probe = std::max(max_probe, probe);
    }
    return int(capacity);
}

}  // namespace

PageTable buildPageTable(const std::vector<glm::ivec3>& coords, const std::vector<char>& visible) {
    PageTable t;
    std::vector<glm::ivec4> bricks;
    std::map<std::tuple<int, int, int>, int> regions;   // region -> its bricks, in a fixed order
    for (size_t slot = 0; slot < coords.size(); ++slot) {
        if (!visible[slot]) continue;
        const glm::ivec3 b = coords[slot];
        bricks.emplace_back(b, int(slot));
        const glm::ivec3 r = kernel::vx_region_of(b);
        ++regions[{r.x, r.y, r.z}];
    }
    t.occupied = bricks.size();
    t.brick_capacity = appendTable(t.entries, bricks, t.max_probe);
    if (t.occupied == 0) return t;
    flaggedBox(coords, visible, t.bricks_min, t.bricks_max);
    // The regions' table only when most regions of the box hold no brick: checking regions costs
    // the march about 15% on one compact cache whose box has a few empty corners
    // (docs/performance.md, "Empty space"), and pays only across wide empty space.
    const glm::ivec3 regions_in_box = kernel::vx_region_of(t.bricks_max) - kernel::vx_region_of(t.bricks_min) + 1;
    if (double(regions_in_box.x) * regions_in_box.y * regions_in_box.z > 2.0 * double(regions.size())) {
        std::vector<glm::ivec4> region_entries;
        for (const auto& [r, count] : regions)
            region_entries.emplace_back(std::get<0>(r), std::get<1>(r), std::get<2>(r), count);
        t.region_capacity = appendTable(t.entries, region_entries, t.region_max_probe);
    }
    t.medium_min = t.bricks_min;
    t.medium_max = t.bricks_max;
    return t;
}

PageTable classifiedPageTable(const BrickAtlas& atlas, const Scene& scene) {
    return classifiedPageTable(atlas, scene.volume(), scene.render.filter);
}

PageTable classifiedPageTable(const BrickAtlas& atlas, const VolumeSpec& volume, Filter filter) {
    const bool tricubic = filter == Filter::Tricubic;
    const auto withFilterReads = [&](const std::vector<char>& flags) { return tricubic ? withNeighbours(atlas.coords, flags) : flags; };
    const std::vector<char> visible = classifyBricks(atlas, volume.material, volume.emission);
    const std::vector<char> medium = withFilterReads(visible);
    if (atlas.motion_reach == 0) return buildPageTable(atlas.coords, medium);
    PageTable pages = buildPageTable(atlas.coords, withFilterReads(withinMotionReach(atlas.coords, visible, atlas.motion_reach)));
    if (!pages.empty()) flaggedBox(atlas.coords, medium, pages.medium_min, pages.medium_max);
    return pages;
}

}  // namespace voxlux
