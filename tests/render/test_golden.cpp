// Golden image: the bundled default scene, small, on the CPU backend, against a committed EXR.
// Any change to the march, the bricking or the default cloud shows up here. After an intended
// change, regenerate with VOXLUX_UPDATE_GOLDEN=1 and say why in the commit.
#include <cmath>
#include <cstdlib>
#include <filesystem>


#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

const std::string kGolden = std::string(VOXLUX_SOURCE_DIR) + "/tests/golden/default_cloud_80x50.exr";

TEST(Golden, DefaultCloudMatchesTheCommittedImage) {
    Scene scene = loadSceneFile(std::string(VOXLUX_SOURCE_DIR) + "/grids/default.json");
    scene.render.width = 80;
    scene.render.height = 50;
    scene.render.backend = Backend::Cpu;
    scene.output.pixel_type = PixelType::Float;
    scene.output.aovs = {AovSpec{"transmittance", std::nullopt}};
    const bool update = std::getenv("VOXLUX_UPDATE_GOLDEN") != nullptr;
    scene.output.path = update ? kGolden : tempDir("golden") + "/default.exr";
    Renderer(scene).renderToFile(std::nullopt, false);
    if (update) GTEST_SKIP() << "golden image rewritten: " << kGolden;

    // Tolerance: float rounding differences between compilers and CPUs (FMA contraction, SIMD
    // width) move pixels by ~1e-6 of their value; a real change to the image moves them by 1e-3+.
    const Exr got_image = readExr(scene.output.path);
    const Exr want_image = readExr(kGolden);
    ASSERT_EQ(got_image.channels, want_image.channels);
    for (const char* channel : {"R", "G", "B", "A", "transmittance.Y"}) {
        const auto& got = got_image.planes.at(channel);
        const auto& want = want_image.planes.at(channel);
        ASSERT_EQ(got.size(), want.size());
        double sq = 0.0, worst = 0.0, peak = 0.0;
        for (size_t i = 0; i < got.size(); ++i) {
            const double d = std::abs(double(got[i]) - want[i]);
            sq += d * d;
            worst = std::max(worst, d);
            peak = std::max(peak, double(std::abs(want[i])));
        }
        EXPECT_GT(peak, 0.1) << channel << ": the golden image must not be empty";
        EXPECT_LT(std::sqrt(sq / got.size()), 1e-4 * peak) << channel;
        EXPECT_LT(worst, 1e-3 * peak) << channel;
    }
}

}  // namespace
}  // namespace voxlux::test
