// Golden images: bundled scenes, small, on the CPU backend, against committed EXRs. Any change
// to the march, the bricking, the lighting or the bundled data shows up here. After an intended
// change, regenerate with VOXLUX_UPDATE_GOLDEN=1 and say why in the commit.
#include <cmath>
#include <cstdlib>
#include <filesystem>


#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// Renders the bundled scene `scene_file` small on the CPU and compares it with the committed
// tests/golden/`golden` (or rewrites that under VOXLUX_UPDATE_GOLDEN=1).
void expectMatchesGolden(const std::string& scene_file, const std::string& golden, int width, int height) {
    const std::string path = sourceDir() + "/tests/golden/" + golden;
    Scene scene = loadSceneFile(sourceDir() + "/grids/" + scene_file);
    scene.render.width = width;
    scene.render.height = height;
    scene.render.backend = Backend::Cpu;
    scene.output.pixel_type = PixelType::Float;
    scene.output.aovs = {AovSpec{"transmittance", std::nullopt}};
    const bool update = std::getenv("VOXLUX_UPDATE_GOLDEN") != nullptr;
    scene.output.path = update ? path : tempDir("golden") + "/" + golden;
    Renderer(scene).renderToFile(std::nullopt, false);
    if (update) GTEST_SKIP() << "golden image rewritten: " << path;

    // Tolerance: float rounding differences between compilers and CPUs (FMA contraction, SIMD
    // width) move pixels by ~1e-6 of their value; a real change to the image moves them by 1e-3+.
    const Exr got_image = readExr(scene.output.path);
    const Exr want_image = readExr(path);
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

TEST(Golden, DefaultCloudMatchesTheCommittedImage) { expectMatchesGolden("default.json", "default_cloud_80x50.exr", 80, 50); }

// The MRI head: the import's grid, the 2D transfer function, propagation with Kniss's indirect
// light and surface shading, the tricubic filter.
TEST(Golden, MriHeadMatchesTheCommittedImage) { expectMatchesGolden("mri_head.json", "mri_head_64x64.exr", 64, 64); }

}  // namespace
}  // namespace voxlux::test
