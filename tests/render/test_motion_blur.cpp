// Velocity motion blur (render.motion_blur; shaders/vx_motion.h): a box moving at constant
// velocity smears into the analytic ramp, reaching past the bricks it occupies (the atlas adds
// them); a still velocity renders bit for bit as no blur; a moving camera equals the medium moving
// the other way; the Monte Carlo reference blurs the same; the Blender fire's velocity grid
// streaks it as a brute-force OpenVDB integration over the shutter says; the scene keys' errors.
#include <glm/gtc/matrix_transform.hpp>
#include <openvdb/tools/Interpolation.h>

#include "backend/backend_choice.h"
#include "scene/camera.h"
#include "scene/scene_json.h"
#include "test_support.h"
#include "volume/velocity.h"

namespace voxlux::test {
namespace {

// A box of extinction kBoxSigma over voxels [24, 39]^3 (voxel size 1, so voxel i sits at world i),
// seen from 1000 units down -z through a 64^2 image whose pixels are one world unit wide at the
// box: pixel column c looks along world x = c + 0.5, row r along y = 63.5 - r.
constexpr float kBoxSigma = 0.1f;
constexpr int kImage = 64;

openvdb::FloatGrid::Ptr movingBox() { return boxGrid({24, 24, 24}, {39, 39, 39}, kBoxSigma); }

// A constant velocity over a box wider than the medium, as a simulation's velocity field is.
openvdb::Vec3SGrid::Ptr constantVelocity(openvdb::Vec3s v) {
    auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    grid->denseFill(openvdb::CoordBBox({0, 16, 16}, {63, 47, 47}), v, true);
    return grid;
}

LoadedVolume withVelocity(openvdb::FloatGrid::Ptr density, openvdb::Vec3SGrid::Ptr velocity) {
    LoadedVolume v = volumeFromGrid(density);
    v.velocity = velocity;
    v.max_speed = maxSpeed(*velocity);
    return v;
}

Scene boxScene(std::optional<MotionBlur> blur) {
    Scene scene;
    scene.render.width = kImage;
    scene.render.height = kImage;
    scene.render.step = 0.25f;
    scene.output.pixel_type = PixelType::Float;
    scene.effects.shadows = ShadowMethod::Raymarch;
    Light key;
    key.type = LightType::Point;
    key.position = {60.0f, 70.0f, 50.0f};
    key.intensity = 4000.0f;
    scene.lights = {key};
    const float fov = 2.0f * glm::degrees(std::atan(32.0f / 1000.0f));
    scene.camera = cameraAlong({32.0f, 32.0f, 32.0f}, {0.0f, 0.0f, -1.0f}, 1000.0f, fov);
    scene.render.motion_blur = blur;
    return scene;
}

// 16 voxels a second at 1 frame a second: over the shutter [-0.25, 0.25] the box moves from 4
// voxels back to 4 ahead along x.
MotionBlur boxBlur(int samples) {
    MotionBlur blur;
    blur.fps = 1.0f;
    blur.samples = samples;
    return blur;
}

RenderImage renderOn(KernelBackend& backend, const Scene& scene, LoadedVolume volume) {
    Renderer renderer(scene, std::move(volume), backend);
    return renderer.render(std::nullopt, false).image;
}

float alphaAt(const RenderImage& img, int x, int y) { return img.pixels[size_t(y) * img.width + x].rgba.w; }

// The box's alpha along a ray down z through world x: the trilinear ramps at its faces (voxel i
// at world i, so density rises over [23, 24] and falls over [39, 40]), 16 voxels deep.
double staticAlpha(double x) {
    const double share = std::clamp(std::min(x - 23.0, 40.0 - x), 0.0, 1.0);
    return 1.0 - std::exp(-double(kBoxSigma) * 16.0 * share);
}

// The analytic smear: the static alpha averaged over the shutter, the box moved 16 t along x.
double smearedAlpha(double x) {
    constexpr int kSteps = 4000;
    double sum = 0.0;
    for (int i = 0; i < kSteps; ++i) sum += staticAlpha(x - 16.0 * (-0.25 + 0.5 * (i + 0.5) / kSteps));
    return sum / kSteps;
}

// The mean alpha of column x over the rows whose rays cross the box's interior in y.
double columnAlpha(const RenderImage& img, int x) {
    double sum = 0.0;
    for (int y = 28; y <= 35; ++y) sum += alphaAt(img, x, y);
    return sum / 8.0;
}

TEST(MotionBlur, MovingBoxSmearsIntoTheAnalyticRamp) {
    auto cpu = makeCpuBackend();
    const auto velocity = constantVelocity({16.0f, 0.0f, 0.0f});
    const RenderImage still = renderOn(*cpu, boxScene(std::nullopt), withVelocity(movingBox(), velocity));
    const RenderImage blurred = renderOn(*cpu, boxScene(boxBlur(64)), withVelocity(movingBox(), velocity));
    // Unblurred, the box's own profile; blurred, its average over the shutter. 64 stratified times
    // a pixel leave at most 1/64 of the box's alpha per pixel; the rows' mean, less.
    for (int x = 16; x < 48; ++x) {
        const double centre = x + 0.5;
        EXPECT_NEAR(columnAlpha(still, x), staticAlpha(centre), 0.01) << "still, column " << x;
        EXPECT_NEAR(columnAlpha(blurred, x), smearedAlpha(centre), 0.01) << "blurred, column " << x;
    }
    // Column 42 lies wholly outside the still box, in brick 5, which holds neither density nor its
    // apron: only the bricks the atlas adds within the motion's reach let the march see the box
    // arrive there.
    EXPECT_EQ(columnAlpha(still, 42), 0.0);
    EXPECT_GT(columnAlpha(blurred, 42), 0.08);
}

TEST(MotionBlur, StillMediumRendersBitForBitAsNoBlur) {
    auto cpu = makeCpuBackend();
    // Still where the box is; one voxel far off moves, so the blur runs (8 rays a pixel, the
    // bricks within reach added) but finds nothing moving.
    const auto still = constantVelocity({0.0f, 0.0f, 0.0f});
    still->tree().setValue({62, 20, 20}, openvdb::Vec3s(16.0f, 0.0f, 0.0f));
    Scene lit = boxScene(std::nullopt);
    Light sky;
    sky.type = LightType::Ambient;
    sky.intensity = 0.3f;
    lit.lights.push_back(sky);
    const RenderImage plain = renderOn(*cpu, lit, withVelocity(movingBox(), still));
    lit.render.motion_blur = boxBlur(8);
    const RenderImage blurred = renderOn(*cpu, lit, withVelocity(movingBox(), still));
    ASSERT_EQ(plain.pixels.size(), blurred.pixels.size());
    size_t differing = 0;
    for (size_t i = 0; i < plain.pixels.size(); ++i) {
        const kernel::VxPixel& a = plain.pixels[i];
        const kernel::VxPixel& b = blurred.pixels[i];
        differing += a.rgba != b.rgba || a.direct != b.direct || a.ambient != b.ambient || a.transmittance != b.transmittance ||
                     a.depth != b.depth;
    }
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(alphaAt(plain, 32, 32), 0.7f);
    // The march ran 8 rays a pixel for it, through the added bricks too.
    EXPECT_GT(blurred.pixels[32 * kImage + 32].samples, 8.0f * plain.pixels[32 * kImage + 32].samples);
}

TEST(MotionBlur, MovingCameraEqualsTheMediumMovingTheOtherWay) {
    auto cpu = makeCpuBackend();
    Scene moving_box = boxScene(boxBlur(16));
    const RenderImage box_moves = renderOn(*cpu, moving_box, withVelocity(movingBox(), constantVelocity({16.0f, 0.0f, 0.0f})));
    // The camera moves -4 to +4 world units along -x (so the box moves +x in the image) over the shutter.
    Scene moving_camera = boxScene(boxBlur(16));
    const glm::mat4 base = cameraToWorld(*moving_camera.camera);
    moving_camera.camera->motion = std::array<glm::mat4, 2>{glm::translate(glm::mat4(1.0f), {4.0f, 0.0f, 0.0f}) * base,
                                                            glm::translate(glm::mat4(1.0f), {-4.0f, 0.0f, 0.0f}) * base};
    const RenderImage camera_moves = renderOn(*cpu, moving_camera, volumeFromGrid(movingBox()));
    double worst = 0.0;
    for (size_t i = 0; i < box_moves.pixels.size(); ++i)
        worst = std::max(worst, double(std::abs(box_moves.pixels[i].rgba.w - camera_moves.pixels[i].rgba.w)));
    EXPECT_LT(worst, 2e-3);
    EXPECT_GT(columnAlpha(camera_moves, 42), 0.08);
}

TEST(MotionBlur, ReferenceHonoursTheShutterTime) {
    auto cpu = makeCpuBackend();
    Scene scene = boxScene(boxBlur(1));
    scene.render.method = RenderMethod::Reference;
    scene.render.reference.spp = 256;
    scene.render.reference.max_bounces = 1;
    const RenderImage ref = renderOn(*cpu, scene, withVelocity(movingBox(), constantVelocity({16.0f, 0.0f, 0.0f})));
    // A time per path, stratified over the pixel's paths. The camera pass's transmittance is ratio
    // tracked at the box's own extinction, so each path's is 0 or 1: over the 8 rows' 2048 paths
    // its standard deviation is at most 0.011.
    for (int x = 18; x < 46; x += 3) EXPECT_NEAR(columnAlpha(ref, x), smearedAlpha(x + 0.5), 0.035) << "column " << x;
}

TEST(MotionBlur, GlBlursAsTheCpuDoesOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    auto cpu = makeCpuBackend();
    const auto velocity = constantVelocity({16.0f, 0.0f, 0.0f});
    const RenderImage a = renderOn(*cpu, boxScene(boxBlur(8)), withVelocity(movingBox(), velocity));
    const RenderImage b = renderOn(*gl, boxScene(boxBlur(8)), withVelocity(movingBox(), velocity));
    double worst = 0.0;
    for (size_t i = 0; i < a.pixels.size(); ++i) worst = std::max(worst, double(std::abs(a.pixels[i].rgba.w - b.pixels[i].rgba.w)));
    EXPECT_LT(worst, 1e-4);
    EXPECT_GT(columnAlpha(b, 42), 0.08);
}

TEST(MotionBlur, SceneKeysAreChecked) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "render": {"motion_blur": {"shutter": [0.25, -0.25]}}})"),
              "shot.json: /render/motion_blur/shutter: expected [open, close] in frames, -1 <= open <= close <= 1");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "render": {"motion_blur": {"samples": 0}}})"),
              "shot.json: /render/motion_blur/samples: must lie in 1..64");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "render": {"motion_blur": true}, "output": {"deep": true}})"),
              "shot.json: /output: deep output is made at one time and render.motion_blur spreads a pixel over the shutter: "
              "turn one of them off");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0],
                              "motion": {"open": {"position": [0, 0, 5], "look_at": [0, 0, 0]}}}})"),
              "shot.json: /camera/motion/close: required key is missing");
}

TEST(MotionBlur, SceneKeysRoundTrip) {
    const Scene s = parseScene(R"({"volume": {"path": "a.vdb"},
        "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0],
                   "motion": {"open": {"position": [-1, 0, 5], "look_at": [0, 0, 0]}, "close": {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 5, 1]}}},
        "render": {"motion_blur": {"shutter": [0, 0.5], "velocity": "vel", "velocity_scale": 0.01, "fps": 25, "samples": 4}}})",
                               "shot.json", "");
    const nlohmann::json written = sceneToJson(s);
    EXPECT_EQ(written["render"]["motion_blur"], nlohmann::json::parse(R"({"shutter": [0, 0.5], "velocity": "vel", "velocity_scale": 0.01,
                                                                           "fps": 25, "samples": 4})"));
    EXPECT_EQ(written["camera"]["motion"]["close"]["matrix"][12], 1.0);
    EXPECT_EQ(written["camera"]["motion"]["open"]["matrix"][12], -1.0);   // the pose, as a matrix
    EXPECT_EQ(sceneToJson(parseScene(written.dump(), "again.json", "")), written);
}

TEST(MotionBlur, ImpossibleReachIsRefusedInOneLine) {
    auto velocity = constantVelocity({16.0f, 0.0f, 0.0f});
    velocity->setName("vel");
    LoadedVolume v = withVelocity(movingBox(), velocity);
    v.file = "box.vdb";
    MotionBlur blur = boxBlur(8);
    EXPECT_EQ(motionReachBricks(v, blur), 1);   // 4 voxels
    blur.velocity_scale = 1000.0f;
    EXPECT_EQ(inputErrorOf([&] { motionReachBricks(v, blur); }),
              "box.vdb: grid 'vel' moves the medium up to 4000 voxels within the shutter (more than 256); check "
              "render.motion_blur.velocity_scale and fps");
}

// The Blender fire at frame 30 seen from the side (z up: the fire rises), its density and
// velocity grids. Blender's velocity is staggered; voxlux averages it onto the voxel centres.
struct FireView {
    LoadedVolume volume;
    Scene scene;
};

FireView fireView(const std::string& file, std::optional<MotionBlur> blur) {
    FireView f;
    f.scene.volume().path = file;
    f.scene.render.width = 48;
    f.scene.render.height = 64;
    f.scene.render.step = 0.25f;
    f.scene.volume().material.density_scale = 60.0f;
    f.scene.effects.shadows = ShadowMethod::None;
    Camera camera;
    camera.position = {1.0f, -4.0f, 1.5f};
    camera.look_at = {1.0f, 1.0f, 1.5f};
    camera.up = {0.0f, 0.0f, 1.0f};
    camera.fov = 40.0f;
    f.scene.camera = camera;
    f.scene.render.motion_blur = blur;
    f.volume = loadVolume(file, f.scene.volume(), blur);
    return f;
}

// Brute force, through OpenVDB's own samplers: the alpha of the ray through pixel (px, py),
// averaged over `times` instants spread evenly over the shutter, each a fine midpoint sum of
// density at x - v(x) t.
double bruteForceAlpha(const FireView& f, const MotionBlur& blur, int px, int py, int times) {
    const auto density = f.volume.density->getConstAccessor();
    const auto velocity = f.volume.velocity->getConstAccessor();
    const openvdb::math::Transform& xf = f.volume.density->transform();
    const Camera& c = *f.scene.camera;
    const glm::mat4 to_world = cameraToWorld(c);
    const float tan_half = std::tan(glm::radians(c.fov) * 0.5f), aspect = 48.0f / 64.0f;
    const glm::vec3 origin(to_world[3]);
    const glm::vec3 dir = glm::normalize(glm::vec3(to_world * glm::vec4((2.0f * (px + 0.5f) / 48.0f - 1.0f) * tan_half * aspect,
                                                                        (1.0f - 2.0f * (py + 0.5f) / 64.0f) * tan_half, -1.0f, 0.0f)));
    const double voxel = xf.voxelSize()[0], step = 0.05 * voxel, scale = f.scene.volume().material.density_scale;
    double sum = 0.0;
    for (int i = 0; i < times; ++i) {
        const double t = blur.shutter_open + (blur.shutter_close - blur.shutter_open) * (i + 0.5) / times;
        double tau = 0.0;
        for (double s = 2.5; s < 6.5; s += step) {
            const glm::vec3 x = origin + dir * float(s + 0.5 * step);
            const openvdb::Vec3d ijk = xf.worldToIndex(openvdb::Vec3d(x.x, x.y, x.z));
            const openvdb::Vec3s v = openvdb::tools::BoxSampler::sample(velocity, ijk);
            const openvdb::Vec3d moved = ijk - openvdb::Vec3d(v) * (blur.velocity_scale / blur.fps * t) / voxel;
            tau += scale * std::max(0.0f, openvdb::tools::BoxSampler::sample(density, moved)) * step;
        }
        sum += 1.0 - std::exp(-tau);
    }
    return sum / times;
}

TEST(MotionBlur, BlenderFireStreaksAsItsVelocitySays) {
    VOXLUX_REQUIRE_SHARED(file, "blender/fire/fluid_data_0030.vdb");
    MotionBlur blur;
    blur.samples = 64;
    blur.velocity_scale = 0.5f;
    const FireView still = fireView(file, std::nullopt);
    const FireView moving = fireView(file, blur);
    ASSERT_TRUE(moving.volume.velocity);
    EXPECT_EQ(moving.volume.velocity->getName(), "velocity");
    auto cpu = makeCpuBackend();
    const RenderImage a = renderOn(*cpu, still.scene, still.volume);
    const RenderImage b = renderOn(*cpu, moving.scene, moving.volume);
    // The pixel the blur changes most: where the fire streaks into air it left clear at the
    // frame's own time.
    int best = 0;
    for (int i = 1; i < 48 * 64; ++i)
        if (b.pixels[i].rgba.w - a.pixels[i].rgba.w > b.pixels[best].rgba.w - a.pixels[best].rgba.w) best = i;
    const int px = best % 48, py = best / 48;
    const float streak = b.pixels[best].rgba.w - a.pixels[best].rgba.w;
    EXPECT_GT(streak, 0.1f) << "pixel " << px << ", " << py;
    EXPECT_NEAR(bruteForceAlpha(moving, blur, px, py, 1), a.pixels[best].rgba.w, 0.01);    // the frame itself
    EXPECT_NEAR(bruteForceAlpha(moving, blur, px, py, 256), b.pixels[best].rgba.w, 0.02);  // over the shutter
}

}  // namespace
}  // namespace voxlux::test
