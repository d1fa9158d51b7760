// Camera matrices and the default framing used by the quick form of `voxlux render`.
#pragma once
#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

// Camera-to-world (camera looks down -Z with +Y up, as OpenEXR's worldToCamera expects).
glm::mat4 cameraToWorld(const Camera& camera);

// The radius of the camera's lens in world units (0 without depth of field): half its aperture,
// focal length / fstop.
float lensRadius(const Camera& camera);

// Perspective projection to NDC in [-1, 1] (OpenEXR's worldToNDC uses it after worldToCamera).
glm::mat4 cameraProjection(const Camera& camera, float aspect);

// World-space axis-aligned box of the index-space box [lo, hi] under `index_to_world`.
void worldBounds(const glm::mat4& index_to_world, glm::vec3 lo, glm::vec3 hi, glm::vec3& out_lo, glm::vec3& out_hi);

// A three-quarter view from above that fits the box in the frame, in the view frame `frame`
// (columns right, up and back: upFrame, viewFrame in volume/up_axis.h); and a key light from the
// upper left of that view.
Camera frameBox(glm::vec3 lo, glm::vec3 hi, float fov, float aspect, const glm::mat3& frame = glm::mat3(1.0f));
Light defaultKeyLight(const glm::mat3& frame = glm::mat3(1.0f));

}  // namespace voxlux
