// A still volume transform moved, turned or scaled in world space about a pivot, as the viewer's
// gizmo drags it, and kept in the form an artist types: translate, rotate (degrees, in the
// transform's own rotate order) and scale. Turning composes the turn with the rotation and reads
// the angles back out of the product (Tait-Bryan angles of the order), so the pose's matrix is
// the turn applied to the old one, to float rounding; the scale stays along the volume's axes.
#pragma once
#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

// The degrees that give `rotation` in `order`, to float rounding near gimbal lock too (the middle
// angle at +-90, where the first angle is 0 and the last carries the turn). The inverse of
// rotationMatrix (scene.h).
glm::vec3 rotationAngles(const glm::mat3& rotation, RotateOrder order);

// `t` (still: no matrix, no keys) moved by `by`, turned by `turn` about `pivot`, or scaled by
// `factor` about `pivot`, all in the scene's world.
VolumeTransform movedBy(VolumeTransform t, glm::vec3 by);
VolumeTransform turnedAbout(VolumeTransform t, const glm::mat3& turn, glm::vec3 pivot);
VolumeTransform scaledAbout(VolumeTransform t, float factor, glm::vec3 pivot);

}  // namespace voxlux
