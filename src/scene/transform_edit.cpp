// Gizmo edits of a still volume transform (transform_edit.h).
#include "scene/transform_edit.h"

#include <cmath>

namespace voxlux {
namespace {

// The axis indices of `order`, first applied first, and +1 when they run x, y, z cyclically.
struct Axes {
    int first, middle, last;
    float parity;
};
Axes axesOf(RotateOrder order) {
    const char* name = kRotateOrderNames[int(order)];
    const int first = name[0] - 'x', middle = name[1] - 'x';
    return {first, middle, name[2] - 'x', (middle - first + 3) % 3 == 1 ? 1.0f : -1.0f};
}

float at(const glm::mat3& m, int row, int column) { return m[column][row]; }   // glm is column-major

}  // namespace

glm::vec3 rotationAngles(const glm::mat3& m, RotateOrder order) {
    // For R = R_k(c) R_j(b) R_i(a) with (i, j, k) of parity s: R[k][i] = -s sin b, and away from
    // gimbal lock tan a = s R[k][j] / R[k][k], tan c = s R[j][i] / R[i][i].
    const Axes x = axesOf(order);
    const int i = x.first, j = x.middle, k = x.last;
    const float s = x.parity;
    const float sin_b = glm::clamp(-s * at(m, k, i), -1.0f, 1.0f);
    glm::vec3 radians(0.0f);
    radians[j] = std::asin(sin_b);
    if (std::abs(sin_b) < 0.99999f) {
        radians[i] = std::atan2(s * at(m, k, j), at(m, k, k));
        radians[k] = std::atan2(s * at(m, j, i), at(m, i, i));
    } else {
        radians[k] = std::atan2(-s * at(m, i, j), at(m, j, j));
    }
    return glm::degrees(radians);
}

VolumeTransform movedBy(VolumeTransform t, glm::vec3 by) {
    t.translate += by;
    return t;
}

VolumeTransform turnedAbout(VolumeTransform t, const glm::mat3& turn, glm::vec3 pivot) {
    // p + T (R S x + t - p) = (T R) S x + (p + T (t - p)).
    t.translate = pivot + turn * (t.translate - pivot);
    t.rotate = rotationAngles(turn * rotationMatrix(t.rotate, t.rotate_order), t.rotate_order);
    return t;
}

VolumeTransform scaledAbout(VolumeTransform t, float factor, glm::vec3 pivot) {
    t.translate = pivot + factor * (t.translate - pivot);
    t.scale *= factor;
    return t;
}

}  // namespace voxlux
