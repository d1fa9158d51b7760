// Rays against triangles, through Embree 3's BVH: the camera's rays into a holdout's mesh
// (holdouts[i].mesh), where each pixel's ray stops. Building the BVH costs O(n log n) over the
// triangles once; a ray then costs O(log n). Thread-safe queries, one ray at a time.
#pragma once
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "scene/mesh_file.h"

namespace voxlux {

class MeshRays {
public:
    // `meshes`, each placed by its matrix of `placements` (its local space to the world).
    MeshRays(const std::vector<const TriangleMesh*>& meshes, const std::vector<glm::mat4>& placements);
    ~MeshRays();
    MeshRays(const MeshRays&) = delete;
    MeshRays& operator=(const MeshRays&) = delete;

    // The distance along `dir` (unit length) from `origin` to the nearest triangle, either side
    // facing; infinity when the ray meets none.
    float nearestHit(const glm::vec3& origin, const glm::vec3& dir) const;

private:
    struct Bvh;
    std::unique_ptr<Bvh> bvh_;
};

}  // namespace voxlux
