// Depth of field (camera.fstop, shaders/vx_pixel.h vx_through_lens): a half-plane slab in the focal
// plane keeps the pinhole's edge; out of focus, its edge spreads as the thin lens's circle of
// confusion says (the fraction of the lens disk whose rays reach the slab), in the march, the GL
// backend and the reference alike; the keys' errors.
#include <cmath>

#include "scene/camera.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kLensImage = 64;
constexpr float kSlabDistance = 10.0f;   // the camera's distance from the slab, along -z

// A slab 0.1 thick at z 0 over x < 0.025 (voxel 0.05, its last voxel at x 0 fading to none at
// 0.05, which holds the optical depth of half a voxel), of optical depth 2 across, seen from z 10
// down -z with a 30-degree view centred on its edge.
Scene slabScene(const std::string& dir) {
    const std::string path = dir + "/slab.vdb";
    openvdb::io::File(path).write({boxGrid({-400, -400, -1}, {0, 400, 1}, 1.0f, 0.05)});
    Scene s;
    s.volumes[0].path = path;
    s.volumes[0].material.density_scale = 20.0f;
    s.render.width = s.render.height = kLensImage;
    s.render.backend = Backend::Cpu;
    s.render.step = 0.25f;
    s.effects.shadows = ShadowMethod::None;
    s.camera = cameraAlong(glm::vec3(0.025f, 0.0f, 0.0f), glm::vec3(0, 0, -1), kSlabDistance, 30.0f);
    Light sky;
    sky.type = LightType::Ambient;
    s.lights = {sky};
    return s;
}

// The lens: f/2 on the 30-degree view's focal length (24 / (2 tan 15 deg) = 44.8 mm) in a world of
// 25 mm units, a radius of 0.448.
Scene throughLens(Scene s, float focus) {
    s.camera->fstop = 2.0f;
    s.camera->world_unit_mm = 25.0f;
    s.camera->focus_distance = focus;
    s.camera->lens_samples = 256;
    return s;
}

// Alpha down each column, over the image's middle rows.
std::vector<double> columnAlpha(const RenderImage& image) {
    std::vector<double> out(kLensImage, 0.0);
    for (int y = kLensImage / 4; y < 3 * kLensImage / 4; ++y)
        for (int x = 0; x < kLensImage; ++x) out[size_t(x)] += image.pixels[size_t(y) * kLensImage + x].rgba.w / (kLensImage / 2.0);
    return out;
}

// The share of a disk of radius 1 beyond the chord at `a` (of its radius) from its centre.
double diskBeyond(double a) {
    if (a <= -1.0) return 1.0;
    if (a >= 1.0) return 0.0;
    return (std::acos(a) - a * std::sqrt(1.0 - a * a)) / M_PI;
}

// Pixel column x looks along tan sx; focused at distance f, its rays meet the slab plane (distance
// d) at x = d sx + L (1 - d / f) from the edge for the lens point's L: the slab (x < 0) covers the
// share of the lens disk beyond L = d sx / (d / f - 1), of the disk's radius R.
double expectedCoverage(int x, float radius, float focus) {
    const double tan_half = std::tan(glm::radians(15.0));
    const double sx = (2.0 * (x + 0.5) / kLensImage - 1.0) * tan_half;
    return diskBeyond(kSlabDistance * sx / (kSlabDistance / focus - 1.0) / radius);
}

TEST(DepthOfField, TheLensIsHalfTheApertureOfTheFocalLengthOverTheFstop) {
    Camera c = *slabScene(tempDir("dof-radius")).camera;
    c.fstop = 2.0f;
    c.world_unit_mm = 25.0f;
    EXPECT_NEAR(lensRadius(c), 24.0 / (2.0 * std::tan(glm::radians(15.0))) / 2.0 / 2.0 / 25.0, 1e-6);
    c.focal_length = 50.0f;   // the view's own focal length when it has one (fov follows it)
    c.fov = glm::degrees(2.0f * std::atan(12.0f / 50.0f));
    EXPECT_NEAR(lensRadius(c), 50.0 / 4.0 / 25.0, 1e-5);
    c.fstop = 0.0f;
    EXPECT_EQ(lensRadius(c), 0.0f);
}

TEST(DepthOfField, AnEdgeInTheFocalPlaneStaysSharp) {
    const Scene scene = slabScene(tempDir("dof-sharp"));
    const std::vector<double> pinhole = columnAlpha(renderScene(scene));
    const std::vector<double> focused = columnAlpha(renderScene(throughLens(scene, kSlabDistance)));
    EXPECT_GT(pinhole[0], 0.8);
    EXPECT_LT(pinhole[kLensImage - 1], 1e-6);
    double largest = 0.0;
    for (int x = 0; x < kLensImage; ++x) largest = std::max(largest, std::abs(pinhole[size_t(x)] - focused[size_t(x)]));
    std::printf("  focused against the pinhole: %.2e\n", largest);
    EXPECT_LT(largest, 1e-3);
}

TEST(DepthOfField, AnEdgeOutOfFocusSpreadsOverTheThinLensCircle) {
    const Scene scene = slabScene(tempDir("dof-blur"));
    const double full = columnAlpha(renderScene(scene))[0];
    const float focus = 5.0f;
    Scene lens = throughLens(scene, focus);
    const float radius = lensRadius(*lens.camera);
    // The circle of confusion, R |1/d - 1/f| at unit distance: 0.0448, 5.4 pixels.
    const double circle_px = radius * std::abs(1.0 / kSlabDistance - 1.0 / focus) / std::tan(glm::radians(15.0)) * kLensImage / 2.0;
    EXPECT_NEAR(circle_px, 5.35, 0.01);
    for (RenderMethod method : {RenderMethod::March, RenderMethod::Reference}) {
        SCOPED_TRACE(int(method));
        lens.render.method = method;
        lens.render.reference.spp = 256;
        lens.render.reference.max_bounces = 1;
        const std::vector<double> blurred = columnAlpha(renderScene(lens));
        double largest = 0.0;
        int spread = 0;   // the columns between all and nothing
        for (int x = 0; x < kLensImage; ++x) {
            largest = std::max(largest, std::abs(blurred[size_t(x)] - full * expectedCoverage(x, radius, focus)));
            spread += blurred[size_t(x)] > 0.02 * full && blurred[size_t(x)] < 0.98 * full;
        }
        std::printf("  %s: against the thin lens %.2e, %d columns between\n", method == RenderMethod::March ? "march" : "reference", largest, spread);
        EXPECT_LT(largest, 0.02);
        EXPECT_GE(spread, 9);   // about the circle's 10.7-pixel diameter
        EXPECT_LE(spread, 12);
    }
}

TEST(DepthOfField, GlBlursAsTheCpuDoesOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = throughLens(slabScene(tempDir("dof-gl")), 5.0f);
    scene.camera->lens_samples = 16;
    const RenderImage cpu = renderScene(scene);
    scene.render.backend = Backend::Gl;
    const RenderImage gpu = renderScene(scene);
    float largest = 0.0f;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) largest = std::max(largest, std::abs(cpu.pixels[i].rgba.w - gpu.pixels[i].rgba.w));
    EXPECT_LE(largest, 1e-4f);
}

TEST(DepthOfField, KeysAreValidated) {
    const std::string v = R"({"volume": {"path": "a.vdb"}, "camera": )";
    // Focused at the look_at's distance unless told, and written back whole.
    const Scene aimed = parseScene(v + R"({"position": [0, 3, 4], "look_at": [0, 0, 0], "fstop": 2.8}})", "shot.json", ".");
    EXPECT_EQ(sceneToJson(aimed)["camera"]["focus_distance"], 5.0);
    EXPECT_EQ(sceneToJson(parseScene(sceneToJson(aimed).dump(), "shot.json", ".")), sceneToJson(aimed));
    EXPECT_EQ(sceneErrorOf(v + R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1], "fstop": 2}})"),
              "shot.json: /camera/focus_distance: is required with fstop when the camera has no look_at");
    EXPECT_EQ(sceneErrorOf(v + R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "focus_distance": 3}})"), "shot.json: /camera/focus_distance: goes with fstop (depth of field)");
    EXPECT_EQ(sceneErrorOf(v + R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "fstop": 0}})"),
              "shot.json: /camera/fstop: must lie in (0, 1e6): the f-number, focal length over the aperture");
    EXPECT_EQ(sceneErrorOf(v + R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "fstop": 2, "lens_samples": 0}})"), "shot.json: /camera/lens_samples: must lie in 1..1024");
    EXPECT_EQ(sceneErrorOf(v + R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "fstop": 2}, "output": {"path": "a.exr", "deep": true}})"),
              "shot.json: /output: deep output is made through a pinhole and camera.fstop spreads a pixel over the lens: turn one of them off");
}

}  // namespace
}  // namespace voxlux::test
