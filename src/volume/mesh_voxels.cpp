#include "volume/mesh_voxels.h"

#include <algorithm>

#include <openvdb/tools/MeshToVolume.h>

#include "core/error.h"

namespace voxlux {

namespace {

constexpr float kOpaqueWithin = 0.5f;   // voxels from the surface where the shell is solid
constexpr float kShellReach = 1.5f;     // voxels from the surface where it ends
constexpr float kFarthest = 1e9f;      // as a mesh file's points
constexpr int kMostVoxelsAcross = 16384;   // across the clip box: 1.6 m in 0.1 mm cells, finer than any light grid

// `polygon` cut to the box [lo, hi] (Sutherland-Hodgman, one face plane at a time): OpenVDB
// voxelises a triangle's whole band, and a ground plane of two triangles a kilometre wide would be
// billions of voxels where the box wants thousands.
std::vector<openvdb::Vec3s> clippedToBox(std::vector<openvdb::Vec3s> polygon, const glm::vec3& lo, const glm::vec3& hi) {
    for (int face = 0; face < 6 && !polygon.empty(); ++face) {
        const int axis = face / 2;
        const bool upper = face % 2 == 1;
        const float bound = upper ? hi[axis] : lo[axis];
        const auto inside = [&](const openvdb::Vec3s& p) { return upper ? p[axis] <= bound : p[axis] >= bound; };
        std::vector<openvdb::Vec3s> out;
        for (size_t i = 0; i < polygon.size(); ++i) {
            const openvdb::Vec3s& a = polygon[i];
            const openvdb::Vec3s& b = polygon[(i + 1) % polygon.size()];
            if (inside(a)) out.push_back(a);
            if (inside(a) != inside(b)) {
                const float t = (bound - a[axis]) / (b[axis] - a[axis]);
                openvdb::Vec3s p = a + (b - a) * t;
                p[axis] = bound;
                out.push_back(p);
            }
        }
        polygon = std::move(out);
    }
    return polygon;
}

}  // namespace

LoadedVolume voxelisedMesh(const TriangleMesh& mesh, const glm::mat4& placement, float voxel_size, const glm::vec3& clip_lo,
                           const glm::vec3& clip_hi, const std::string& file) {
    initOpenVdb();
    // The triangles cut to the clip box grown by the shell's reach, and by that reach again: a
    // kept voxel's nearest point of the mesh is never cut away.
    const glm::vec3 reach(kShellReach * voxel_size), lo = clip_lo - reach, hi = clip_hi + reach;
    const glm::vec3 cut_lo = lo - reach, cut_hi = hi + reach;
    const glm::vec3 side = (hi - lo) / voxel_size;
    if (!(std::max({side.x, side.y, side.z}) <= float(kMostVoxelsAcross)))
        throw InputError(file + ": its shadowing cells would be more than " + std::to_string(kMostVoxelsAcross) +
                         " voxels across: raise the holdout's voxel_size or lower its shadow_reach");
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    for (const glm::uvec3& t : mesh.triangles) {
        std::vector<openvdb::Vec3s> corners;
        for (const unsigned i : {t.x, t.y, t.z}) {
            const glm::vec3 w = glm::vec3(placement * glm::vec4(mesh.points[i], 1.0f));
            if (!(glm::all(glm::lessThanEqual(glm::abs(w), glm::vec3(kFarthest)))))
                throw InputError(file + ": the holdout's transform places a point beyond +-1e9");
            corners.emplace_back(w.x, w.y, w.z);
        }
        const std::vector<openvdb::Vec3s> piece = clippedToBox(std::move(corners), cut_lo, cut_hi);
        const unsigned first = unsigned(points.size());
        points.insert(points.end(), piece.begin(), piece.end());
        for (unsigned i = 2; i < piece.size(); ++i) triangles.emplace_back(first, first + i - 1, first + i);
    }
    // Index 0 at the box's corner, not the world's origin: a set far from the origin in fine cells
    // keeps small indices, which floats resolve and OpenVDB's 32-bit coordinates hold.
    const auto transform = openvdb::math::Transform::createLinearTransform(voxel_size);
    const glm::vec3 corner = glm::floor(lo / voxel_size) * voxel_size;
    transform->postTranslate(openvdb::Vec3d(corner.x, corner.y, corner.z));
    openvdb::FloatGrid::Ptr cells;
    if (triangles.empty()) {
        cells = openvdb::FloatGrid::create(0.0f);
        cells->setTransform(transform);
    } else {
        cells = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*transform, points, triangles, {}, kShellReach + 1.0f);
        // Distance (world units) to coverage; the band's background (its far distance) becomes 0.
        for (auto v = cells->beginValueOn(); v; ++v) {
            const float coverage = std::clamp((kShellReach - *v / voxel_size) / (kShellReach - kOpaqueWithin), 0.0f, 1.0f);
            if (coverage > 0.0f)
                v.setValue(coverage);
            else
                v.setValue(0.0f), v.setActiveState(false);
        }
        cells->tree().root().setBackground(0.0f, true);
        cells->clipGrid(openvdb::BBoxd(openvdb::Vec3d(lo.x, lo.y, lo.z), openvdb::Vec3d(hi.x, hi.y, hi.z)));
        cells->tree().prune();
    }
    cells->setGridClass(openvdb::GRID_FOG_VOLUME);
    cells->setName("density");
    LoadedVolume out;
    out.file = file;
    out.index_to_world = indexToWorld(*cells, file);
    out.density = cells;
    return out;
}

}  // namespace voxlux
