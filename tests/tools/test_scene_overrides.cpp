// Flags that set scene keys are read together (so flags that only make sense together pass), and
// a refused result names the flag that brought the refused value.
#include <gtest/gtest.h>

#include "test_support.h"
#include "tools/scene_overrides.h"

namespace voxlux::test {
namespace {

Scene referenceScene() {
    Scene s;
    s.volume().path = "cloud.vdb";
    s.render.method = RenderMethod::Reference;
    s.render.backend = Backend::Cpu;
    return s;
}

TEST(SceneOverrides, FlagsThatOnlyMakeSenseTogetherPass) {
    SceneOverrides o;
    o.backend = "gl";      // refused alone: the reference runs on the CPU
    o.method = "march";
    const Scene s = applyOverrides(referenceScene(), o);
    EXPECT_EQ(s.render.backend, Backend::Gl);
    EXPECT_EQ(s.render.method, RenderMethod::March);
}

TEST(SceneOverrides, TheFlagThatBroughtTheRefusedValueIsNamed) {
    SceneOverrides o;
    o.backend = "gl";
    o.step = 0.5f;
    EXPECT_EQ(inputErrorOf([&] { applyOverrides(referenceScene(), o); }),
              "--backend: /render/method: reference runs on the cpu backend only (render.backend is \"gl\")");
    o = {};
    o.sets = {"render.step=0.25", "render.step=100"};
    EXPECT_EQ(inputErrorOf([&] { applyOverrides(referenceScene(), o); }),
              "--set 'render.step=100': /render/step: must lie in [0.01, 64] voxels");
}

}  // namespace
}  // namespace voxlux::test
