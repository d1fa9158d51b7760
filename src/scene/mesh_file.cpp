#include "scene/mesh_file.h"

#include <cmath>
#include <filesystem>

#include <assimp/scene.h>

#include "core/error.h"
#include "scene/assimp_import.h"

namespace voxlux {
namespace {

constexpr float kFarthest = 1e9f;   // as a camera file's and a transform's bound

// Appends the triangles of `mesh`, placed by `world`.
void gatherMesh(const aiMesh& mesh, const glm::mat4& world, const std::string& file, TriangleMesh& out) {
    const unsigned first = unsigned(out.points.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        const glm::vec3 p = glm::vec3(world * glm::vec4(mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z, 1.0f));
        if (!(std::abs(p.x) <= kFarthest && std::abs(p.y) <= kFarthest && std::abs(p.z) <= kFarthest))
            throw InputError(file + ": mesh '" + std::string(mesh.mName.C_Str()) + "' has a point beyond +-1e9");
        out.points.push_back(p);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        for (unsigned i = 0; i < face.mNumIndices; ++i)
            if (face.mIndices[i] >= mesh.mNumVertices)
                throw InputError(file + ": mesh '" + std::string(mesh.mName.C_Str()) + "' has a face past its last vertex");
        for (unsigned i = 2; i < face.mNumIndices; ++i)   // a polygon as a fan; points and lines have none
            out.triangles.emplace_back(first + face.mIndices[0], first + face.mIndices[i - 1], first + face.mIndices[i]);
    }
}

TriangleMesh meshOf(const ImportedScene& scene, const std::string& file) {
    TriangleMesh out;
    // The node tree walked with a stack of its own: a file's depth is not the program's stack's.
    std::vector<std::pair<const aiNode*, glm::mat4>> pending{{scene->mRootNode, glm::mat4(1.0f)}};
    while (!pending.empty()) {
        const auto [node, parent] = pending.back();
        pending.pop_back();
        const glm::mat4 world = parent * glmMatrix(node->mTransformation);
        for (unsigned m = 0; m < node->mNumMeshes; ++m) {
            if (node->mMeshes[m] >= scene->mNumMeshes)
                throw InputError(file + ": a node names mesh " + std::to_string(node->mMeshes[m]) + ", which the file lacks");
            gatherMesh(*scene->mMeshes[node->mMeshes[m]], world, file, out);
        }
        for (unsigned c = 0; c < node->mNumChildren; ++c) pending.emplace_back(node->mChildren[c], world);
    }
    if (out.triangles.empty()) throw InputError(file + ": has no triangles");
    return out;
}

bool isMeshExtension(const std::string& ext) { return ext == "obj" || ext == "gltf" || ext == "glb" || ext == "fbx"; }

void checkFormat(const std::string& ext, const std::string& file) {
    if (!isMeshExtension(ext))
        throw InputError(file + ": not a mesh file voxlux reads (expected .obj, .gltf, .glb or .fbx)");
}

}  // namespace

bool isMeshFile(const std::string& path) { return isMeshExtension(lowerExtension(path)); }

TriangleMesh readMeshFile(const std::string& path) {
    const std::string ext = lowerExtension(path);
    checkFormat(ext, path);
    if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": cannot open mesh file");
    return meshOf(importSceneFile(path, ext), path);
}

TriangleMesh parseMeshFile(const std::string& bytes, const std::string& ext, const std::string& file) {
    checkFormat(ext, file);
    return meshOf(importSceneBytes(bytes, ext, file), file);
}

}  // namespace voxlux
