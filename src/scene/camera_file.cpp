#include "scene/camera_file.h"

#include <cmath>
#include <filesystem>

#include <assimp/scene.h>

#include "core/error.h"
#include "scene/assimp_import.h"
#include "scene/chan_file.h"

namespace voxlux {
namespace {

// Whether an animation of `scene` moves `node` or one of its parents.
bool animated(const aiScene& scene, const aiNode* node) {
    for (; node; node = node->mParent)
        for (unsigned a = 0; a < scene.mNumAnimations; ++a)
            for (unsigned c = 0; c < scene.mAnimations[a]->mNumChannels; ++c)
                if (scene.mAnimations[a]->mChannels[c]->mNodeName == node->mName) return true;
    return false;
}

// The camera named `name` (the first when empty) of an imported scene (`gltf`: a glTF's, else an
// FBX's), posed by its node.
CameraFile cameraOf(const ImportedScene& scene, const std::string& file, bool gltf, const std::string& name) {
    if (scene->mNumCameras == 0) throw InputError(file + ": has no camera");
    const aiCamera* camera = nullptr;
    std::string names;
    for (unsigned i = 0; i < scene->mNumCameras; ++i) {
        const std::string n = scene->mCameras[i]->mName.C_Str();
        names += (names.empty() ? "'" : ", '") + n + "'";
        if (!camera && (name.empty() || n == name)) camera = scene->mCameras[i];
    }
    if (!camera) throw InputError(file + ": has no camera named '" + name + "' (its cameras are " + names + ")");
    const aiNode* node = scene->mRootNode->FindNode(camera->mName);
    if (!node) throw InputError(file + ": camera '" + std::string(camera->mName.C_Str()) + "' hangs from no node");
    if (animated(*scene, node))
        throw InputError(file + ": camera '" + std::string(camera->mName.C_Str()) +
                         "' is animated: voxlux reads a glTF or FBX camera's still pose so far; export it as a Nuke .chan for camera.file");
    glm::mat4 world(1.0f);
    for (const aiNode* n = node; n; n = n->mParent) world = glmMatrix(n->mTransformation) * world;
    // The camera's own frame in its node: where it sits, where it looks and which way is up.
    const glm::vec3 at(camera->mPosition.x, camera->mPosition.y, camera->mPosition.z);
    const glm::vec3 look(camera->mLookAt.x, camera->mLookAt.y, camera->mLookAt.z);
    const glm::vec3 up_hint(camera->mUp.x, camera->mUp.y, camera->mUp.z);
    const glm::vec3 right = glm::cross(look, up_hint);
    if (!(glm::length(look) > 0.0f) || !(glm::length(right) > 0.0f))
        throw InputError(file + ": camera '" + std::string(camera->mName.C_Str()) + "' has no view direction and up");
    const glm::vec3 back = -glm::normalize(look), x = glm::normalize(right), y = glm::cross(back, x);
    const glm::mat4 local(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(back, 0.0f), glm::vec4(at, 1.0f));
    CameraFile out;
    out.path = file;
    out.name = camera->mName.C_Str();
    out.pose.matrix = world * local;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite((*out.pose.matrix)[c][r]) || std::abs((*out.pose.matrix)[c][r]) > 1e9f)
                throw InputError(file + ": camera '" + out.name + "' has a transform beyond +-1e9");
    // The frame is fitted by its height. assimp's glTF importer keeps yfov times the aspect in
    // mHorizontalFOV; its FBX importer keeps FBX's FieldOfView, the whole horizontal angle.
    if (camera->mHorizontalFOV > 0.0f && camera->mAspect > 0.0f) {
        const float vertical = gltf ? camera->mHorizontalFOV / camera->mAspect
                                    : 2.0f * std::atan(std::tan(0.5f * camera->mHorizontalFOV) / camera->mAspect);
        const float degrees = glm::degrees(vertical);
        if (degrees > 0.0f && degrees < 180.0f) out.vertical_fov = {degrees};
    }
    return out;
}

}  // namespace

CameraFile parseAssimpCamera(const std::string& bytes, const std::string& hint, const std::string& file, const std::string& name) {
    return cameraOf(importSceneBytes(bytes, hint, file), file, hint != "fbx", name);
}

bool isChanFile(const std::string& path) { return lowerExtension(path) == "chan"; }

CameraFile readCameraFile(const std::string& path, const std::string& name, RotateOrder order) {
    const std::string ext = lowerExtension(path);
    if (isChanFile(path)) {
        const ChanTrack track = readChanFile(path);
        CameraFile out;
        out.path = path;
        out.pose.keys = track.keys;
        out.pose.rotate_order = order;
        out.pose.chan = path;
        out.vertical_fov = track.vertical_fov;
        return out;
    }
    if (ext != "gltf" && ext != "glb" && ext != "fbx")
        throw InputError(path + ": not a camera file voxlux reads (expected .chan, .gltf, .glb or .fbx)");
    if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": cannot open camera file");
    return cameraOf(importSceneFile(path, ext), path, ext != "fbx", name);
}

Camera posedCamera(const Camera& camera, double frame) {
    Camera posed = camera;
    if (camera.focal_length > 0.0f) posed.fov = glm::degrees(2.0f * std::atan(camera.film_back.y / (2.0f * camera.focal_length)));
    if (!camera.file) return posed;
    const CameraFile& f = *camera.file;
    posed.matrix = volumeTransformMatrix(f.pose, frame);
    if (f.vertical_fov.size() == 1) {
        posed.fov = f.vertical_fov[0];
    } else if (f.vertical_fov.size() > 1) {   // per key, blended as the pose is
        const KeyBlend k = keyBlend(f.pose.keys, frame);
        posed.fov = f.vertical_fov[k.a] + k.weight * (f.vertical_fov[k.b] - f.vertical_fov[k.a]);
    }
    return posed;
}

}  // namespace voxlux
