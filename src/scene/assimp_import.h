// A glTF, FBX or OBJ file read through assimp by the importer of the format its extension names,
// and by no other. assimp's own Importer::ReadFile falls back to every importer whose signature
// check the bytes pass when that format's importer refuses them; some of those (Quick3D, MD5, ...)
// trust sizes written in the file and ask for terabytes. voxlux reads scenes only in the formats it
// names, so a file its format's importer refuses is refused. Cost: that importer's parse of the
// whole file, with no post-processing.
#pragma once
#include <memory>
#include <string>

#include <assimp/matrix4x4.h>
#include <glm/glm.hpp>

struct aiScene;

namespace voxlux {

struct AiSceneDelete {
    void operator()(aiScene* scene) const;
};
using ImportedScene = std::unique_ptr<aiScene, AiSceneDelete>;

// assimp's matrix (rows) as glm's (columns).
glm::mat4 glmMatrix(const aiMatrix4x4& m);

// `path`'s extension in lower case, without its dot ("" when it has none).
std::string lowerExtension(const std::string& path);

// The scene in the file at `path`, read as `ext` ("gltf", "glb", "fbx", "obj"). Throws InputError
// "<path>: not a .<ext> file assimp reads (<assimp's reason>)".
ImportedScene importSceneFile(const std::string& path, const std::string& ext);

// The same for a file held in `bytes`, named `file` in messages; files it refers to are not found.
ImportedScene importSceneBytes(const std::string& bytes, const std::string& ext, const std::string& file);

}  // namespace voxlux
