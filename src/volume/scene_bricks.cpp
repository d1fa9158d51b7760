#include "volume/scene_bricks.h"

#include <algorithm>
#include <cassert>

namespace voxlux {

bool isEmptyRange(const kernel::VxPageRange& r) { return r.capacity == 0 || glm::any(glm::greaterThan(r.lo, r.hi)); }

bool growByPageRange(const kernel::VxPageRange& r, const glm::mat4& index_to_space, glm::vec3& lo, glm::vec3& hi) {
    if (isEmptyRange(r)) return false;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::ivec3 b(corner & 1 ? r.hi.x + 1 : r.lo.x, corner & 2 ? r.hi.y + 1 : r.lo.y, corner & 4 ? r.hi.z + 1 : r.lo.z);
        const glm::vec3 p(index_to_space * glm::vec4(glm::vec3(b * VX_BRICK), 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return true;
}

SceneBricks joinVolumeBricks(const std::vector<const BrickAtlas*>& atlases, const std::vector<const PageTable*>& pages) {
    assert(atlases.size() == pages.size() && !atlases.empty());
    SceneBricks out;
    out.atlas.index_to_world = atlases.front()->index_to_world;
    for (size_t v = 0; v < atlases.size(); ++v) {
        const BrickAtlas& a = *atlases[v];
        const PageTable& p = *pages[v];
        const int slot_offset = int(out.atlas.slots());
        kernel::VxPageRange r{};
        r.lo = p.bricks_min;
        r.first = int(out.pages.entries.size());
        r.hi = p.bricks_max;
        r.capacity = p.brick_capacity;
        r.max_probe = p.max_probe;
        out.ranges.push_back(r);
        out.index_to_world.push_back(a.index_to_world);
        out.atlas.coords.insert(out.atlas.coords.end(), a.coords.begin(), a.coords.end());
        out.atlas.density.insert(out.atlas.density.end(), a.density.begin(), a.density.end());
        out.atlas.density_range.insert(out.atlas.density_range.end(), a.density_range.begin(), a.density_range.end());
        out.atlas.active_voxels += a.active_voxels;
        // Its sources', colour's and velocity's blocks after the volumes' before: source s of slot
        // i at emission_offset + s * emission_stride past the tap's index i * 729 + voxel in the
        // joined density, its colour and velocity at color_offset and velocity_offset past it (3
        // floats a voxel).
        VolumeChannels c;
        c.emission_first = int(out.emission_grid_max.size());
        c.emission_count = int(a.emission_sources);
        c.emission_stride = int(a.slots()) * VX_BRICK_VOXELS;
        c.emission_offset = int(out.atlas.emission.size()) - slot_offset * VX_BRICK_VOXELS;
        c.color = !a.color.empty();
        c.color_offset = int(out.atlas.color.size() / 3) - slot_offset * VX_BRICK_VOXELS;
        c.velocity = !a.velocity.empty() && a.motion_reach > 0;
        c.velocity_offset = int(out.atlas.velocity.size() / 3) - slot_offset * VX_BRICK_VOXELS;
        out.channels.push_back(c);
        out.atlas.emission.insert(out.atlas.emission.end(), a.emission.begin(), a.emission.end());
        out.atlas.color.insert(out.atlas.color.end(), a.color.begin(), a.color.end());
        if (c.velocity) {
            const glm::mat3 to_index = glm::inverse(glm::mat3(a.index_to_world));
            for (size_t i = 0; i < a.velocity.size(); i += 3) {
                const glm::vec3 v = to_index * glm::vec3(a.velocity[i], a.velocity[i + 1], a.velocity[i + 2]);
                out.atlas.velocity.insert(out.atlas.velocity.end(), {v.x, v.y, v.z});
            }
            out.atlas.motion_reach = std::max(out.atlas.motion_reach, a.motion_reach);
        }
        for (size_t s = 0; s < a.emission_sources; ++s) out.emission_grid_max.push_back(a.emissionGridMax(s));
        // The bricks' entries only, their slots moved past the volumes before.
        for (int i = 0; i < p.brick_capacity; ++i) {
            glm::ivec4 e = p.entries[size_t(i)];
            if (e.w != VX_PAGE_EMPTY) e.w += slot_offset;
            out.pages.entries.push_back(e);
        }
        out.pages.occupied += p.occupied;
        out.pages.max_probe = std::max(out.pages.max_probe, p.max_probe);
    }
    out.pages.brick_capacity = int(out.pages.entries.size());
    return out;
}

}  // namespace voxlux
