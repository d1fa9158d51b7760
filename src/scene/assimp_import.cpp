#include "scene/assimp_import.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include <assimp/BaseImporter.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/scene.h>

#include "core/error.h"

namespace voxlux {
namespace {

bool listsExtension(const aiImporterDesc& desc, const std::string& ext) {
    std::istringstream extensions(desc.mFileExtensions ? desc.mFileExtensions : "");
    for (std::string e; extensions >> e;)
        if (e == ext) return true;
    return false;
}

// The first importer that lists `ext` and recognises the file (glTF 1 and glTF 2 share their
// extensions), reading it through `io`.
ImportedScene importThrough(Assimp::IOSystem& io, const std::string& name, const std::string& ext, const std::string& file) {
    Assimp::Importer importer;
    std::string problem = "no importer of its format recognises it";
    for (size_t i = 0; i < importer.GetImporterCount(); ++i) {
        Assimp::BaseImporter* format = importer.GetImporter(i);
        if (!listsExtension(*importer.GetImporterInfo(i), ext) || !format->CanRead(name, &io, true)) continue;
        ImportedScene scene(format->ReadFile(&importer, name, &io));
        if (scene && scene->mRootNode) return scene;
        problem = format->GetErrorText().empty() ? "it has no scene" : format->GetErrorText();
        break;
    }
    throw InputError(file + ": not a ." + ext + " file assimp reads (" + problem + ")");
}

}  // namespace

glm::mat4 glmMatrix(const aiMatrix4x4& m) {
    glm::mat4 out;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) out[c][r] = m[r][c];
    return out;
}

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext.empty() ? ext : ext.substr(1);
}

void AiSceneDelete::operator()(aiScene* scene) const { delete scene; }

ImportedScene importSceneFile(const std::string& path, const std::string& ext) {
    Assimp::DefaultIOSystem io;
    return importThrough(io, path, ext, path);
}

ImportedScene importSceneBytes(const std::string& bytes, const std::string& ext, const std::string& file) {
    Assimp::MemoryIOSystem io(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), nullptr);
    return importThrough(io, std::string(AI_MEMORYIO_MAGIC_FILENAME) + "." + ext, ext, file);
}

}  // namespace voxlux
