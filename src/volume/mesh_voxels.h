// A holdout's mesh as the cells that shadow the volumes in its stead (a shadow-only volume, made
// by renderedScene): OpenVDB's unsigned distance to the triangles (tools::meshToUnsignedDistance-
// Field, which needs no closed surface) turned into coverage: 1 within half a voxel of the surface,
// falling linearly to 0 at a voxel and a half. The mesh is a shell two voxels thick, opaque at the
// density scale renderedScene gives it, so a ground plane or a wall blocks light as a closed
// character does; its inside is never reached by light. Only the mesh within the clip box (the
// scene's volumes' box grown by the holdout's shadow_reach) is voxelised: each triangle is cut to
// the box first, so a ground plane of two triangles a kilometre wide costs what its part in the box
// does. Cost: OpenVDB's conversion, about the shell's voxels (the surface's area in the box over a
// voxel's face), never the box's volume; refused past 16384 voxels across the box.
#pragma once
#include <string>

#include <glm/glm.hpp>

#include "scene/mesh_file.h"
#include "volume/vdb_loader.h"

namespace voxlux {

// `mesh` placed by `placement` (its local space to the world), as cells of edge `voxel_size`
// (world units) over the world box [clip_lo, clip_hi]; named `file` in the volume's messages.
LoadedVolume voxelisedMesh(const TriangleMesh& mesh, const glm::mat4& placement, float voxel_size, const glm::vec3& clip_lo,
                           const glm::vec3& clip_hi, const std::string& file);

}  // namespace voxlux
