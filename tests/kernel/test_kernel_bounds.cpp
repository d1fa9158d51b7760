// The CPU kernel's index checks (VOXLUX_BOUNDS_CHECK, on in the sanitizer build tests/run.sh
// makes): an index outside a light, channel or array aborts with its name instead of reading
// another cell's memory. Other builds skip these tests.
#include <gtest/gtest.h>

#include "kernel/cpu_kernel.h"
#include "lighting/extinction_sat/kernel/cpu_sat_kernel.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

#ifdef VX_BOUNDS_CHECK
constexpr bool kChecked = true;
#else
constexpr bool kChecked = false;
#endif

#define SKIP_UNLESS_CHECKED() \
    if (!kChecked) GTEST_SKIP() << "built without VOXLUX_BOUNDS_CHECK (the sanitizer build runs this)"

TEST(KernelBounds, ALightPastTheLightArrayTraps) {
    SKIP_UNLESS_CHECKED();
    const std::vector<kernel::VxLight> lights(2);
    kernel::CpuKernel k;
    k.lights = lights;
    EXPECT_EQ(k.vx_light(1).type, 0);
    EXPECT_DEATH(k.vx_light(2), "voxlux: kernel light index 2 outside \\[0, 2\\)");
    EXPECT_DEATH(k.vx_light(-1), "voxlux: kernel light index -1 outside \\[0, 2\\)");
}

// The march over a real medium with one light more than the light array holds: the class of
// defect the disabled-light crash was (a count and an array that disagree).
TEST(KernelBounds, AMarchWithMoreLightsThanItsArrayTraps) {
    SKIP_UNLESS_CHECKED();
    Scene scene;
    scene.render.width = scene.render.height = 8;
    Light key;
    key.type = LightType::Point;
    key.position = glm::vec3(8.0f, 30.0f, 8.0f);
    scene.lights = {key};
    Camera camera;
    camera.position = glm::vec3(8.0f, 8.0f, 60.0f);
    camera.look_at = glm::vec3(8.0f);
    auto prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {15, 15, 15}, 0.5f)), scene, camera);
    kernel::CpuKernel k = bindCpuKernel(prepared->inputs);
    kernel::CpuKernel::VxDeepRay deep;
    EXPECT_GT(k.vx_render_pixel(4, 4, deep).rgba.w, 0.0f);
    k.P.light_count = 2;
    EXPECT_DEATH(k.vx_render_pixel(4, 4, deep), "voxlux: kernel light index 1 outside \\[0, 1\\)");
}

TEST(KernelBounds, ACacheChannelPastTheCellTraps) {
    SKIP_UNLESS_CHECKED();
    const std::vector<float> cache(2 * 2 * 2 * 3, 1.0f);
    kernel::CpuKernel k;
    k.cache = cache;
    k.L.extinction_sat.world_to_cache = glm::mat4(1.0f);
    k.L.extinction_sat.cache_dims = glm::ivec3(2);
    k.L.extinction_sat.cache_floats = 3;
    const auto cell = k.vx_cache_cell(glm::vec3(1.0f));
    EXPECT_EQ(k.vx_cache_value(cell, 2), 1.0f);
    // Channel 3 would read channel 0 of the next cell: no memory error, a wrong shadow.
    EXPECT_DEATH(k.vx_cache_value(cell, 3), "voxlux: kernel light-cache channel index 3 outside \\[0, 3\\)");
}

TEST(KernelBounds, ASatPlanePastThePlanesTraps) {
    SKIP_UNLESS_CHECKED();
    kernel::CpuSatKernel k;
    k.S.planes = 1;
    k.S.quantum = glm::vec4(0.5f);
    EXPECT_EQ(k.vx_sat_quantum(0), 0.5f);
    EXPECT_DEATH(k.vx_sat_quantum(1), "voxlux: kernel SAT plane index 1 outside \\[0, 1\\)");
}

}  // namespace
}  // namespace voxlux::test
