// The brick walk's region step (shaders/vx_dda.h) against the brick walk itself: leaving a region
// that holds no brick in one step must land where stepping brick by brick does, bit for bit, or
// the march would move samples between bricks or lose them.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

#include "kernel/cpu_kernel_data.h"

namespace voxlux::test {
namespace {

using kernel::CpuKernelData;

struct Ray {
    glm::vec3 o, d;
};

// Random rays, and the rays that tie: axis-parallel ones, diagonals from points on brick planes
// (all three axes cross a plane at the same t), rays starting exactly on a region's corner.
std::vector<Ray> testRays() {
    std::vector<Ray> rays;
    std::mt19937 rng(19);
    std::uniform_real_distribution<float> pos(-300.0f, 300.0f), dir(-1.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) rays.push_back({{pos(rng), pos(rng), pos(rng)}, glm::normalize(glm::vec3(dir(rng), dir(rng), dir(rng)))});
    const glm::vec3 parallel[] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {1, 1, 0}, {0, -1, 1}, {1, 1, 1}, {-1, 1, -1}, {-1, -1, -1}};
    const glm::vec3 starts[] = {{0, 0, 0}, {64, -64, 8}, {3.5f, 7.25f, -9.0f}, {-128, 0, 64}};
    for (const glm::vec3& p : parallel)
        for (const glm::vec3& s : starts) rays.push_back({s, glm::normalize(p)});
    return rays;
}

bool sameState(const CpuKernelData::VxDda& a, const CpuKernelData::VxDda& b) {
    return a.brick == b.brick && a.t_next == b.t_next && a.t == b.t;
}

TEST(BrickWalk, LeavingARegionLandsWhereTheBrickWalkDoes) {
    CpuKernelData k;
    int leaves = 0, wrong = 0;
    for (const Ray& ray : testRays()) {
        CpuKernelData::VxDda s = k.vx_dda_begin(ray.o, ray.d, 0.0f, 5000.0f);
        for (int region = 0; region < 8; ++region) {
            const glm::ivec3 r = kernel::vx_region_of(s.brick);
            CpuKernelData::VxDda walked = s;
            while (kernel::vx_region_of(walked.brick) == r) k.vx_dda_advance(walked);
            CpuKernelData::VxDda jumped = s;
            k.vx_dda_leave_region(jumped, r);
            ++leaves;
            if (!sameState(walked, jumped) && ++wrong <= 5)
                ADD_FAILURE() << "ray from (" << ray.o.x << ", " << ray.o.y << ", " << ray.o.z << ") along (" << ray.d.x << ", "
                              << ray.d.y << ", " << ray.d.z << "), region " << region << ": walked to brick (" << walked.brick.x
                              << ", " << walked.brick.y << ", " << walked.brick.z << ") at t " << walked.t << ", jumped to ("
                              << jumped.brick.x << ", " << jumped.brick.y << ", " << jumped.brick.z << ") at t " << jumped.t;
            s = walked;
        }
    }
    EXPECT_EQ(wrong, 0);
    std::printf("  %d region leaves, %d unlike the brick walk\n", leaves, wrong);
}

}  // namespace
}  // namespace voxlux::test
