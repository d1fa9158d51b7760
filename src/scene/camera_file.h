// The shot camera from another package (camera.file), not retyped as JSON:
//  - Nuke's .chan (src/scene/chan_file.h): translate and rotate per frame, turned in the camera's
//    rotate_order (Nuke's default zxy), and the vertical field of view where the file has it;
//  - a glTF 2.0 (.gltf, .glb) or FBX scene, read with assimp: the camera node's world transform
//    (its parents' too) and its lens. Its still pose only, so far: an animated camera is refused.
// The camera looks down its -Z with +Y up, as glTF's, Nuke's and voxlux's do; positions are in the
// file's units (glTF: metres; FBX: the file's own, centimetres from Maya), which must be the
// scene's. Cost: one pass over a .chan's lines; assimp's import of the whole glTF/FBX file, once,
// when the scene is read.
#pragma once
#include <string>

#include "scene/scene.h"

namespace voxlux {

// Whether `path` names a Nuke .chan (its extension, in any case), rather than a glTF or FBX scene.
bool isChanFile(const std::string& path);

// The camera of the file at `path` (its extension says which kind); `name` picks a glTF/FBX camera
// by its node's name ("" = the first), `order` turns a .chan's rotations. Throws InputError naming
// the file and the problem.
CameraFile readCameraFile(const std::string& path, const std::string& name, RotateOrder order);

// The camera of the glTF or FBX file held in `bytes` (`hint`: the extension, "gltf", "glb" or
// "fbx"), named `file` in messages: what readCameraFile does with such a file, from memory.
CameraFile parseAssimpCamera(const std::string& bytes, const std::string& hint, const std::string& file, const std::string& name);

// `camera` at `frame`: its file's pose (held before the first key and after the last) as its
// matrix, and its file's field of view there where the file has one; the focal length and film
// back as fov otherwise, when the camera has a focal length. A camera without either is as it is.
Camera posedCamera(const Camera& camera, double frame);

}  // namespace voxlux
