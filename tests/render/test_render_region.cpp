// A render region (render.region, as Cycles' border and Arnold's region): the pixels inside are
// the whole image's, to the bit, on each backend and in the Monte Carlo reference; the pixels
// outside are empty (transparent, transmittance 1) and never marched.
#include <filesystem>

#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// Renders the default cloud at 48x32 with `flags`, whole and with the region [0.25, 0.375] to
// [0.625, 0.75] (pixels 12..30 x 12..24), and compares every channel.
void expectRegionMatchesTheWholeImage(const std::string& name, const std::string& flags) {
    const std::string dir = tempDir("region_" + name);
    const std::string base = "render " + sourceDir() + "/grids/default.json --res 48x32 --pixel-type float " +
                             "--aovs direct,transmittance " + flags;
    CliResult r = runCli(base + " -o " + dir + "/whole.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = runCli(base + " --set 'render.region=[0.25,0.375,0.625,0.75]' -o " + dir + "/region.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Exr whole = readExr(dir + "/whole.exr"), region = readExr(dir + "/region.exr");
    ASSERT_EQ(region.width, 48);
    size_t inside = 0, lit = 0;
    for (const auto& [channel, plane] : whole.planes)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 48; ++x) {
                const size_t i = size_t(y) * 48 + x;
                const float got = region.planes.at(channel)[i];
                if (x >= 12 && x < 30 && y >= 12 && y < 24) {
                    ASSERT_EQ(got, plane[i]) << name << " " << channel << " at " << x << "," << y;
                    inside += channel == "A";
                    lit += channel == "A" && got > 0.1f;
                } else {
                    ASSERT_EQ(got, channel == "transmittance.Y" ? 1.0f : 0.0f) << name << " " << channel << " at " << x << "," << y;
                }
            }
    EXPECT_EQ(inside, 18u * 12u);
    EXPECT_GT(lit, 18u * 12u / 2) << "the region holds the cloud";
}

TEST(RenderRegion, TheMarchFillsTheRegionAsTheWholeImage) {
    expectRegionMatchesTheWholeImage("cpu", "--backend cpu");
}

TEST(RenderRegion, TheReferenceFillsTheRegionAsTheWholeImage) {
    expectRegionMatchesTheWholeImage("reference", "--backend cpu --method reference --spp 4");
}

TEST(RenderRegion, TheMarchFillsTheRegionAsTheWholeImageOnGl) {
    VOXLUX_REQUIRE_GL(gl);   // skips without one
    expectRegionMatchesTheWholeImage("gl", "--backend gl --filter trilinear");
}

// The march reads the region: setting it on a renderer that has rendered re-runs the march (and
// nothing before it), and the image changes.
TEST(RenderRegion, SettingARegionRerunsTheMarchAlone) {
    Scene scene = loadSceneFile(sourceDir() + "/grids/default.json");
    scene.render.width = 32;
    scene.render.height = 24;
    scene.render.backend = Backend::Cpu;
    Renderer renderer(scene);
    const RenderImage whole = renderer.render(std::nullopt, false).image;
    scene.render.region = std::array<float, 4>{0.0f, 0.0f, 0.5f, 0.5f};
    renderer.setScene(scene);
    const FrameResult r = renderer.render(std::nullopt, false);
    std::vector<std::string> ran;
    for (const auto& [stage, seconds] : r.stage_seconds) ran.push_back(stage);
    EXPECT_EQ(ran, std::vector<std::string>{"march"});
    // The centre pixel (the first of the quadrant past the region) was marched before, and is empty now.
    const size_t centre = size_t(scene.render.height / 2) * scene.render.width + scene.render.width / 2;
    EXPECT_LT(whole.pixels[centre].transmittance, 0.9f) << "the cloud must cover the centre for the test to tell";
    EXPECT_EQ(r.image.pixels[centre].transmittance, 1.0f);
    const size_t inside = size_t(scene.render.height / 4) * scene.render.width + scene.render.width / 4;
    EXPECT_EQ(r.image.pixels[inside].rgba, whole.pixels[inside].rgba);
}

TEST(RenderRegion, ARegionOutsideTheImageIsRefused) {
    const std::string dir = tempDir("region_bad");
    const CliResult r = runCli("render " + sourceDir() + "/grids/default.json --set 'render.region=[0.5,0,0.4,1]' -o " +
                               dir + "/x.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --set 'render.region=[0.5,0,0.4,1]': /render/region: expected [x_min, y_min, x_max, y_max], fractions "
                     "of the image with 0 <= min < max <= 1\n");
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.exr"));
}

}  // namespace
}  // namespace voxlux::test
