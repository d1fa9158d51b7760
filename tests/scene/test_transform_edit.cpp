// The gizmo's edits of a volume transform (scene/transform_edit.h): the angles read out of a
// rotation give it back in every rotate order, at gimbal lock too; a turn or a scale about a pivot
// is that turn or scale applied to the old pose's matrix, and keeps the pivot where it was.
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "scene/transform_edit.h"

namespace voxlux::test {
namespace {

glm::mat4 around(glm::vec3 pivot, const glm::mat4& m) {
    return glm::translate(glm::mat4(1.0f), pivot) * m * glm::translate(glm::mat4(1.0f), -pivot);
}

TEST(TransformEdit, AnglesReadBackTheRotationInEveryOrder) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> angle(-179.0f, 179.0f);
    for (int order = 0; order < 6; ++order) {
        const RotateOrder o = RotateOrder(order);
        const int middle = kRotateOrderNames[order][1] - 'x';
        for (int k = 0; k < 56; ++k) {
            glm::vec3 degrees(angle(random), angle(random), angle(random));
            // At gimbal lock and near it, where the first angle is poorly defined.
            const float near_lock[6] = {90.0f, -90.0f, 89.8f, -89.95f, 89.999f, 90.2f};
            if (k < 6) degrees[middle] = near_lock[k];
            const glm::mat3 r = rotationMatrix(degrees, o);
            const glm::mat3 back = rotationMatrix(rotationAngles(r, o), o);
            EXPECT_LE(largestDifference(glm::mat4(r), glm::mat4(back)), 2e-6f) << kRotateOrderNames[order] << " k " << k;
        }
    }
    // Away from gimbal lock the angles themselves come back.
    const glm::vec3 angles = rotationAngles(rotationMatrix(glm::vec3(30, -20, 75), RotateOrder::Zxy), RotateOrder::Zxy);
    EXPECT_NEAR(angles.x, 30.0f, 1e-3f);
    EXPECT_NEAR(angles.y, -20.0f, 1e-3f);
    EXPECT_NEAR(angles.z, 75.0f, 1e-3f);
}

TEST(TransformEdit, ATurnAboutAPivotIsTheTurnAppliedToTheOldPose) {
    VolumeTransform t;
    t.translate = glm::vec3(3, -1, 2);
    t.rotate = glm::vec3(10, 40, -25);
    t.scale = glm::vec3(2, 0.5f, 1.5f);   // not uniform: it stays along the volume's own axes
    t.rotate_order = RotateOrder::Yzx;
    const glm::vec3 pivot(1, 2, -3);
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(33.0f), glm::normalize(glm::vec3(1, 2, 0.5f)));
    const VolumeTransform turned = turnedAbout(t, glm::mat3(turn), pivot);
    EXPECT_LE(largestDifference(volumeTransformMatrix(turned), around(pivot, turn) * volumeTransformMatrix(t)), 2e-5f);
    EXPECT_EQ(turned.scale, t.scale);
    EXPECT_EQ(turned.rotate_order, RotateOrder::Yzx);
}

TEST(TransformEdit, AScaleAboutAPivotKeepsThePivotAndScalesTheRest) {
    VolumeTransform t;
    t.translate = glm::vec3(3, -1, 2);
    t.rotate = glm::vec3(0, 90, 0);
    const glm::vec3 pivot(1, 2, -3);
    const VolumeTransform scaled = scaledAbout(t, 1.5f, pivot);
    EXPECT_LE(largestDifference(volumeTransformMatrix(scaled), around(pivot, glm::scale(glm::mat4(1.0f), glm::vec3(1.5f))) * volumeTransformMatrix(t)),
              1e-5f);
    EXPECT_EQ(scaled.scale, glm::vec3(1.5f));
    EXPECT_EQ(movedBy(t, glm::vec3(1, 0, -1)).translate, glm::vec3(4, -1, 1));
}

}  // namespace
}  // namespace voxlux::test
