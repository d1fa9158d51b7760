// Camera moves of the viewer, with the conventions of Houdini's and Maya's viewports: orbit turns
// the camera about its look-at point (around the camera's up axis, then its right axis), pan moves
// both in the image plane, dolly moves the camera towards the look-at point, and frame keeps the
// view direction but fits a box. All work on position / look_at / up; a camera given as a matrix
// is turned into that form first, its look-at point as far ahead as the point it orbits.
#pragma once
#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

// `camera` without a matrix: the same view as position, look_at and up, with look_at as far
// ahead as `pivot` is from the camera.
Camera lookAtForm(const Camera& camera, glm::vec3 pivot);

// Turns by `yaw` degrees about `up`, then `pitch` degrees about the camera's right axis; the
// pitch stops 1 degree short of looking straight along up.
Camera orbit(const Camera& camera, float yaw, float pitch);

// Moves position and look_at by `offset` (fractions of the view's height at the look-at point,
// x to the right, y up).
Camera pan(const Camera& camera, glm::vec2 offset);

// Scales the distance to the look-at point by `factor` (< 1 closer), never below 1e-3 of it.
Camera dolly(const Camera& camera, float factor);

// Looks at the centre of the box [lo, hi] from the current direction, from where its bounding
// sphere fills the vertical field of view.
Camera frameAlong(const Camera& camera, glm::vec3 lo, glm::vec3 hi);

// Where world point `p` lands in an image of `size` pixels (x right, y down), and whether it is
// in front of the camera.
bool projectToImage(const Camera& camera, glm::vec2 size, glm::vec3 p, glm::vec2& pixel);

}  // namespace voxlux
