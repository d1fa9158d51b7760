// The light-cache stage end to end: what a scene change recomputes and what it keeps, the memory
// budget, and SAT-cone shadows against the ray-marched reference on real smoke.
#include <cmath>
#include <limits>
#include <filesystem>

#include "lighting/extinction_sat/kernel/light_cache.h"
#include "lighting/light_grid.h"
#include "render/renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// A CPU render of `vdb` at width x height with the given density scale, no lights yet.
Scene cpuScene(const std::string& vdb, int width, int height, float density_scale) {
    Scene s;
    s.volume().path = vdb;
    s.render.width = width;
    s.render.height = height;
    s.render.backend = Backend::Cpu;
    s.volume().material.density_scale = density_scale;
    return s;
}

Scene ballScene(const std::string& vdb) {
    Scene s = cpuScene(vdb, 48, 40, 4.0f);
    s.effects.shadows = ShadowMethod::SatCone;
    s.effects.ambient_occlusion = AmbientOcclusion{};
    s.effects.light_resolution = 32;
    Light key, fill, ambient;
    key.direction = glm::normalize(glm::vec3(-1, -1, -0.5f));
    key.intensity = 5.0f;
    fill.type = LightType::Point;
    fill.position = glm::vec3(0.5f, 0.2f, 0.0f);  // inside the ball
    fill.intensity = 0.5f;
    ambient.type = LightType::Ambient;
    ambient.intensity = 0.3f;
    s.lights = {key, fill, ambient};
    return s;
}

bool has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }
bool ran(const FrameResult& r, const std::string& stage) {
    return std::any_of(r.stage_seconds.begin(), r.stage_seconds.end(), [&](const auto& p) { return p.first == stage; });
}

float rgbaAt(const FrameResult& r, size_t i, int c) { return r.image.pixels[i].rgba[c]; }

void expectSameImage(const FrameResult& a, const FrameResult& b) {
    ASSERT_EQ(a.image.pixels.size(), b.image.pixels.size());
    for (size_t i = 0; i < a.image.pixels.size(); ++i)
        for (int c = 0; c < 4; ++c) ASSERT_EQ(rgbaAt(a, i, c), rgbaAt(b, i, c)) << "pixel " << i;
}

TEST(LightStage, AChangeRecomputesOnlyWhatItInvalidates) {
    const std::string vdb = writeBall(tempDir("light_stage"));
    Scene scene = ballScene(vdb);
    Renderer renderer(scene);
    const FrameResult first = renderer.render(std::nullopt, false);
    for (const char* stage : {"load", "brick", "light_grid", "sat", "light_cache", "march"}) EXPECT_TRUE(ran(first, stage)) << stage;
    EXPECT_TRUE(first.reused.empty());

    // The same scene again: every stage is reused, the march too.
    const FrameResult again = renderer.render(std::nullopt, false);
    for (const char* stage : {"load", "brick", "classify", "camera", "light_grid", "sat", "light_cache", "march"})
        EXPECT_TRUE(has(again.reused, stage)) << stage;
    EXPECT_TRUE(again.stage_seconds.empty());
    expectSameImage(first, again);

    // Moving the point light recomputes its cone only; the image is what a fresh render gives.
    scene.lights[1].position = glm::vec3(-0.6f, 0.3f, 0.4f);
    renderer.setScene(scene);
    const FrameResult moved = renderer.render(std::nullopt, false);
    EXPECT_TRUE(has(moved.reused, "sat"));
    EXPECT_TRUE(has(moved.reused, "ambient"));
    EXPECT_TRUE(has(moved.reused, "shadow of light 0"));
    EXPECT_FALSE(has(moved.reused, "shadow of light 1"));
    EXPECT_TRUE(ran(moved, "light_cache"));
    expectSameImage(moved, Renderer(scene).render(std::nullopt, false));

    // A brighter key light changes no optical depth: the light cache is reused, the image changes.
    scene.lights[0].intensity = 9.0f;
    renderer.setScene(scene);
    const FrameResult brighter = renderer.render(std::nullopt, false);
    EXPECT_FALSE(ran(brighter, "light_cache"));
    EXPECT_TRUE(ran(brighter, "march"));
    EXPECT_NE(brighter.image.pixels[20 * 48 + 24].rgba.x, moved.image.pixels[20 * 48 + 24].rgba.x);
    expectSameImage(brighter, Renderer(scene).render(std::nullopt, false));

    // A denser material invalidates the grid, the SAT and every channel, but not the bricks.
    scene.volume().material.density_scale = 6.0f;
    renderer.setScene(scene);
    const FrameResult denser = renderer.render(std::nullopt, false);
    EXPECT_TRUE(has(denser.reused, "brick"));
    for (const char* stage : {"light_grid", "sat", "light_cache"}) EXPECT_TRUE(ran(denser, stage)) << stage;
    expectSameImage(denser, Renderer(scene).render(std::nullopt, false));
}

TEST(LightStage, PassesTheSceneDoesNotNeedNeverRun) {
    const std::string vdb = writeBall(tempDir("light_stage_idle"));
    Scene scene = ballScene(vdb);
    scene.lights.pop_back();  // no ambient light: nothing for AO to occlude
    Renderer shadows_only(scene);
    FrameResult r = shadows_only.render(std::nullopt, false);
    EXPECT_TRUE(ran(r, "light_cache"));
    ASSERT_NE(shadows_only.lightingOutput<LightCache>(), nullptr);
    EXPECT_EQ(shadows_only.lightingOutput<LightCache>()->ambient_channel, -1);
    EXPECT_EQ(shadows_only.lightingOutput<LightCache>()->channels, 2);   // one cone channel per light
    scene.effects.shadows = ShadowMethod::Raymarch;  // and no SAT shadows: no light cache at all
    r = Renderer(scene).render(std::nullopt, false);
    for (const char* stage : {"light_grid", "sat", "light_cache"}) {
        EXPECT_FALSE(ran(r, stage)) << stage;
        EXPECT_FALSE(has(r.reused, stage)) << stage;
    }
}

TEST(LightStage, MemoryBudgetLowersTheResolutionAndSaysSo) {
    std::string warning;
    const glm::vec3 extent(400, 200, 100);
    const int r = fitLightResolution(extent, 256, 1, 2, size_t(16) << 20, warning);
    EXPECT_LT(r, 256);
    EXPECT_LE(lightGridBytes(lightGridDims(extent, r), 1, 2), size_t(16) << 20);
    EXPECT_GT(lightGridBytes(lightGridDims(extent, r + 1), 1, 2), size_t(16) << 20);
    EXPECT_EQ(warning, "light cache of 256 cells needs " +
                           std::to_string(lightGridBytes(lightGridDims(extent, 256), 1, 2) >> 20) +
                           " MiB, over effects.light_memory_mb = 16; using " + std::to_string(r) + " cells instead");
    std::string none;
    EXPECT_EQ(fitLightResolution(extent, 64, 1, 2, size_t(16) << 20, none), 64);
    EXPECT_TRUE(none.empty());
    // A huge budget still stops where 32-bit kernel indices would overflow (4 planes of 1024^3).
    std::string indices;
    const int big = fitLightResolution(glm::vec3(1000), 1024, 4, 4, size_t(1) << 50, indices);
    EXPECT_TRUE(lightGridIndexable(lightGridDims(glm::vec3(1000), big), 4, 4));
    EXPECT_FALSE(lightGridIndexable(lightGridDims(glm::vec3(1000), big + 1), 4, 4));
    EXPECT_EQ(indices, "light cache of 1024 cells is beyond the kernel's 32-bit indices (SAT or light cache over 2^31 "
                       "values); using " + std::to_string(big) + " cells instead");

    const std::string vdb = writeBall(tempDir("light_budget"));
    Scene scene = ballScene(vdb);
    scene.effects.light_resolution = 160;
    scene.effects.light_memory_mb = 1;
    const FrameResult small = Renderer(scene).render(std::nullopt, false);
    ASSERT_EQ(small.warnings.size(), 1u);
    EXPECT_NE(small.warnings[0].find("light cache of 160 cells needs"), std::string::npos) << small.warnings[0];
}

// Hard inputs through the whole light stage: NaN, infinite and huge voxels, an HDR light inside the
// medium, and an empty frame. No NaN reaches the image; the oddities are counted.
TEST(LightStage, HostileVoxelsAndEmptyFramesStayFinite) {
    const std::string dir = tempDir("light_hostile");
    auto grid = boxGrid({-12, -12, -12}, {12, 12, 12}, 1.0f, 0.1);
    auto acc = grid->getAccessor();
    acc.setValue({0, 0, 0}, std::numeric_limits<float>::quiet_NaN());
    acc.setValue({3, 0, 0}, std::numeric_limits<float>::infinity());
    acc.setValue({0, 5, 0}, 1e30f);
    acc.setValue({0, 0, 6}, -4.0f);
    openvdb::io::File(dir + "/hostile.vdb").write({grid});
    Scene scene = ballScene(dir + "/hostile.vdb");
    scene.lights[0].intensity = 1e6f;                     // HDR
    scene.lights[1].position = glm::vec3(0.05f, 0.0f, 0.0f);  // inside, beside the NaN voxel
    scene.effects.color_bleeding = 1.0f;
    const FrameResult r = Renderer(scene).render(std::nullopt, false);
    for (const auto& px : r.image.pixels)
        for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(px.rgba[c]));
    std::string warnings;
    for (const auto& w : r.warnings) warnings += w + "\n";
    EXPECT_NE(warnings.find("2 NaN/Inf voxels set to 0"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("1 negative voxels set to 0"), std::string::npos) << warnings;
    // The 1e30 voxel is clamped in the light grid, so it does not take the SAT's precision
    // from the rest: the point light beside it is still shadowed by the ordinary medium.
    EXPECT_NE(warnings.find("1 light-grid cells clamped to an optical depth of 10000 per cell"), std::string::npos)
        << warnings;

    openvdb::io::File(dir + "/empty.vdb").write({boxGrid({0, 0, 0}, {-1, -1, -1}, 0.0f, 0.1)});
    scene.volume().path = dir + "/empty.vdb";
    const FrameResult blank = Renderer(scene).render(std::nullopt, true);
    EXPECT_TRUE(blank.empty);
    for (const char* stage : {"light_grid", "sat", "light_cache"}) EXPECT_FALSE(ran(blank, stage)) << stage;
    for (const auto& px : blank.image.pixels) ASSERT_EQ(px.rgba.w, 0.0f);
}

TEST(LightStage, GridDimsFollowTheLongestSide) {
    EXPECT_EQ(lightGridDims(glm::vec3(400, 200, 100), 128), glm::ivec3(128, 64, 32));
    EXPECT_EQ(lightGridDims(glm::vec3(8, 8, 1), 64), glm::ivec3(64, 64, 8));
    EXPECT_EQ(lightGridDims(glm::vec3(100, 3, 100), 10), glm::ivec3(10, 1, 10));
}

// RMSE of rgb between two renders, and the reference's mean.
double rgbRmse(const FrameResult& a, const FrameResult& ref) {
    double sum = 0.0;
    for (size_t i = 0; i < a.image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.image.pixels[i].rgba[c]) - ref.image.pixels[i].rgba[c];
            sum += d * d;
        }
    return std::sqrt(sum / double(3 * a.image.pixels.size()));
}

// On real smoke, narrow SAT cones approach the ray-marched shadows, and more cuboids per cone
// bring them closer.
TEST(LightStage, NarrowConesApproachRayMarchedShadowsOnSmoke) {
    VOXLUX_REQUIRE_SHARED(smoke, "arnold-usd/smoke.vdb");
    Scene scene = cpuScene(smoke, 96, 128, 2.0f);
    Light key;
    key.direction = glm::normalize(glm::vec3(-0.6f, -0.7f, -0.3f));
    key.intensity = 6.0f;
    scene.lights = {key};
    const FrameResult reference = Renderer(scene).render(std::nullopt, false);
    scene.effects.shadows = ShadowMethod::None;
    const double unshadowed = rgbRmse(Renderer(scene).render(std::nullopt, false), reference);
    scene.effects.shadows = ShadowMethod::SatCone;
    scene.effects.light_resolution = 128;
    scene.effects.cone = {0.5f, 0, 0.1f};
    double last = unshadowed;
    for (int samples : {12, 20, 50}) {
        scene.effects.cone.samples = samples;
        const double e = rgbRmse(Renderer(scene).render(std::nullopt, false), reference);
        std::printf("  %d cuboids: rgb rmse %.4g (unshadowed %.4g)\n", samples, e, unshadowed);
        EXPECT_LT(e, last) << samples << " cuboids";
        last = e;
    }
    EXPECT_LT(last, 0.25 * unshadowed);
}

}  // namespace
}  // namespace voxlux::test
