// Camera matrices and the default framing used by the quick form of `voxlux render`.
#pragma once
#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

// Camera-to-world (camera looks down -Z with +Y up, as OpenEXR's worldToCamera expects).
glm::mat4 cameraToWorld(const Camera& camera);

// Perspective projection to NDC in [-1, 1] (OpenEXR's worldToNDC uses it after worldToCamera).
glm::mat4 cameraProjection(const Camera& camera, float aspect);

// World-space axis-aligned box of the index-space box [lo, hi] under `index_to_world`.
void worldBounds(const glm::mat4& index_to_world, glm::vec3 lo, glm::vec3 hi, glm::vec3& out_lo, glm::vec3& out_hi);

// The world axis `up_axis` (0 x, 1 y, 2 z) as the camera frame's up, and the axes of a right-handed
// frame around it: right, up and back (towards a front-facing camera). Y-up is (x, y, z); Z-up, as
// Blender's, is (x, z, -y).
glm::mat3 upFrame(int up_axis);

// A three-quarter view from above that fits the box in the frame, with `up_axis` up; and a key
// light from the upper left of that view.
Camera frameBox(glm::vec3 lo, glm::vec3 hi, float fov, float aspect, int up_axis = 1);
Light defaultKeyLight(int up_axis = 1);

}  // namespace voxlux
