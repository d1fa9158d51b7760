// A holdout's mesh (holdouts[i].mesh): the triangles of an OBJ, glTF 2.0 (.gltf, .glb) or FBX file,
// read with assimp (scene/assimp_import.h), each mesh placed by its node's world transform (its
// parents' too), polygons split into fans and points and lines left out. Positions are in the
// file's units, which must be the scene's. Cost: assimp's import of the whole file, then one copy
// of its vertices and faces.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace voxlux {

struct TriangleMesh {
    std::vector<glm::vec3> points;
    std::vector<glm::uvec3> triangles;     // indices into points
};

// Whether voxlux reads `path` as a mesh (its extension, in any case: obj, gltf, glb, fbx).
bool isMeshFile(const std::string& path);

// The mesh of the file at `path`. Throws InputError "<path>: <problem>": a file it cannot open,
// a format it does not read, a file without a triangle, a point beyond +-1e9.
TriangleMesh readMeshFile(const std::string& path);

// The same for the file held in `bytes` (`ext`: its format's extension), named `file` in messages.
TriangleMesh parseMeshFile(const std::string& bytes, const std::string& ext, const std::string& file);

}  // namespace voxlux
