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

double at(const glm::dmat3& m, int row, int column) { return m[column][row]; }   // glm is column-major

// The turn by `radians` about coordinate axis `axis`.
glm::dmat3 axisTurn(int axis, double radians) {
    const int p = (axis + 1) % 3, q = (axis + 2) % 3;
    glm::dmat3 t(1.0);
    t[p][p] = t[q][q] = std::cos(radians);
    t[p][q] = std::sin(radians);
    t[q][p] = -std::sin(radians);
    return t;
}

}  // namespace

glm::vec3 rotationAngles(const glm::mat3& rotation, RotateOrder order) {
    // For R = R_k(c) R_j(b) R_i(a) with (i, j, k) of parity s, R's row k is
    // (-s sin b, s cos b sin a, cos b cos a) in columns (i, j, k). So a and b come from row k; c
    // from what is left once they are undone, R R_i(a)^T R_j(b)^T = R_k(c), which holds to
    // rounding however poorly a is defined near gimbal lock (cos b -> 0, where c absorbs a's error;
    // at the lock itself a is 0).
    const Axes x = axesOf(order);
    const int i = x.first, j = x.middle, k = x.last;
    const double s = x.parity;
    const glm::dmat3 m(rotation);
    glm::dvec3 radians(0.0);
    const double cos_b = std::hypot(at(m, k, j), at(m, k, k));
    radians[i] = cos_b > 1e-7 ? std::atan2(s * at(m, k, j), at(m, k, k)) : 0.0;
    radians[j] = std::atan2(-s * at(m, k, i), cos_b);
    const glm::dmat3 left = m * glm::transpose(axisTurn(i, radians[i])) * glm::transpose(axisTurn(j, radians[j]));
    const int p = (k + 1) % 3, q = (k + 2) % 3;
    radians[k] = std::atan2(at(left, q, p), at(left, p, p));
    return glm::vec3(glm::degrees(radians));
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
