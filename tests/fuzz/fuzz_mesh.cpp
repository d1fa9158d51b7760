// Fuzzes the holdout mesh readers (holdouts[i].mesh): the first byte picks the kind (an OBJ, a
// glTF, a binary glTF or an FBX scene read with assimp), the rest is the file; the mesh is then
// voxelised into its shadowing cells over a small box and met by a camera ray. Bad input must throw
// InputError; anything else is a defect.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "render/mesh_rays.h"
#include "scene/mesh_file.h"
#include "volume/mesh_voxels.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string bytes(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        const char* kinds[] = {"obj", "gltf", "glb", "fbx"};
        const std::string kind = kinds[data[0] % 4];
        const voxlux::TriangleMesh mesh = voxlux::parseMeshFile(bytes, kind, "fuzz." + kind);
        for (const glm::uvec3& t : mesh.triangles)
            if (t.x >= mesh.points.size() || t.y >= mesh.points.size() || t.z >= mesh.points.size()) std::abort();
        const voxlux::LoadedVolume cells = voxlux::voxelisedMesh(mesh, glm::mat4(1.0f), 0.1f, glm::vec3(-1.0f), glm::vec3(1.0f), "fuzz." + kind);
        for (auto v = cells.density->cbeginValueOn(); v; ++v)
            if (!(*v > 0.0f && *v <= 1.0f)) std::abort();   // coverage
        const voxlux::MeshRays rays({&mesh}, {glm::mat4(1.0f)});
        const float hit = rays.nearestHit(glm::vec3(0.0f, 0.0f, 5.0f), glm::vec3(0.0f, 0.0f, -1.0f));
        if (!(hit >= 0.0f)) std::abort();   // a distance or infinity, never NaN
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
