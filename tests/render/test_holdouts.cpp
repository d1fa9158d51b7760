// Depth holdouts (scene key `holdouts`, src/render/holdout_stage.h): a surface behind the medium
// leaves the image bit for bit, one in front of it leaves nothing, one through the middle cuts the
// rays as a medium that ends there does; ray distances are camera-space Z over the ray's cosine;
// the reference and the GL backend cut as the CPU march does; bad depth images are refused by name.
#include <filesystem>
#include <fstream>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <glm/gtx/component_wise.hpp>

#include "core/error.h"
#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kHoldoutSize = 20;
constexpr float kCameraZ = 12.0f;   // the camera's distance from the origin along +z, looking down -z

// A box of extinction 3 per world unit over voxels [-20, 20] in x and y and [z0, 20] in z (voxel
// 0.1: the box's front face at world z 2), written to `dir`/`name`.
std::string writeBox(const std::string& dir, const std::string& name, int z0) {
    auto grid = boxGrid({-20, -20, z0}, {20, 20, 20}, 1.0f, 0.1);
    const std::string path = dir + "/" + name;
    openvdb::io::File(path).write({grid});
    return path;
}

// The box seen along -z under a white ambient light alone, unoccluded: a pixel's light is
// albedo * (1 - T), so it follows the optical depth the ray gathers and nothing else.
Scene boxScene(const std::string& file) {
    Scene s;
    s.volumes[0].path = file;
    s.volumes[0].material.density_scale = 3.0f;
    s.render.width = s.render.height = kHoldoutSize;
    s.render.backend = Backend::Cpu;
    s.render.step = 0.5f;
    s.effects.shadows = ShadowMethod::None;
    s.camera = cameraAlong(glm::vec3(0.0f), glm::vec3(0, 0, -1), kCameraZ, 30.0f);
    Light sky;
    sky.type = LightType::Ambient;
    s.lights = {sky};
    s.output.aovs = {{"ambient", std::nullopt}, {"depth", std::nullopt}, {"transmittance", std::nullopt}};
    return s;
}

Scene heldOut(Scene s, const std::string& depth, bool ray_distance = false) {
    s.holdouts = {Holdout{depth, "Z", ray_distance}};
    return s;
}

float largestDifference(const RenderImage& a, const RenderImage& b) {
    float largest = 0.0f;
    for (size_t i = 0; i < a.pixels.size(); ++i) largest = std::max(largest, glm::compMax(glm::abs(a.pixels[i].rgba - b.pixels[i].rgba)));
    return largest;
}

TEST(Holdouts, ASurfaceBehindTheMediumLeavesTheImageBitForBit) {
    const std::string dir = tempDir("holdout-behind");
    const std::string box = writeBox(dir, "box.vdb", -20);
    writeDepthExr(dir + "/far.exr", kHoldoutSize, kHoldoutSize, [](int, int) { return 100.0f; });
    for (RenderMethod method : {RenderMethod::March, RenderMethod::Reference}) {
        Scene scene = boxScene(box);
        scene.render.method = method;
        scene.render.reference.spp = 4;
        const RenderImage open = renderScene(scene), cut = renderScene(heldOut(scene, dir + "/far.exr"));
        ASSERT_GT(open.pixels[size_t(kHoldoutSize / 2 * kHoldoutSize + kHoldoutSize / 2)].rgba.w, 0.9f);
        for (size_t i = 0; i < open.pixels.size(); ++i) {
            ASSERT_EQ(open.pixels[i].rgba, cut.pixels[i].rgba) << i;
            ASSERT_EQ(open.pixels[i].depth, cut.pixels[i].depth) << i;
        }
    }
}

TEST(Holdouts, ASurfaceInFrontOfTheMediumLeavesNothing) {
    const std::string dir = tempDir("holdout-front");
    const std::string box = writeBox(dir, "box.vdb", -20);
    writeDepthExr(dir + "/near.exr", kHoldoutSize, kHoldoutSize, [](int, int) { return 5.0f; });
    for (RenderMethod method : {RenderMethod::March, RenderMethod::Reference}) {
        Scene scene = heldOut(boxScene(box), dir + "/near.exr");
        scene.render.method = method;
        scene.render.reference.spp = 4;
        for (const kernel::VxPixel& p : renderScene(scene).pixels) {
            ASSERT_EQ(p.rgba, glm::vec4(0.0f));
            ASSERT_EQ(p.ambient, glm::vec3(0.0f));
            ASSERT_EQ(p.transmittance, 1.0f);
        }
    }
}

// Cut through the middle, the box renders as the box whose back half is missing: that box's
// density falls from full to 0 over the voxel behind its last one (trilinear), which holds the
// optical depth of half a voxel, so it ends where the holdout's plane does, at world z 0.05.
// Given as camera-space Z, and as the distance along each pixel's ray.
TEST(Holdouts, ASurfaceThroughTheMiddleCutsAsTheMediumEndingThere) {
    const std::string dir = tempDir("holdout-middle");
    const std::string box = writeBox(dir, "box.vdb", -20), half = writeBox(dir, "half.vdb", 1);
    const float plane = kCameraZ - 0.05f;
    writeDepthExr(dir + "/z.exr", kHoldoutSize, kHoldoutSize, [&](int, int) { return plane; });
    const float tan_half = std::tan(glm::radians(15.0f));
    writeDepthExr(dir + "/distance.exr", kHoldoutSize, kHoldoutSize, [&](int x, int y) {
        const float sx = (2.0f * (float(x) + 0.5f) / kHoldoutSize - 1.0f) * tan_half, sy = (1.0f - 2.0f * (float(y) + 0.5f) / kHoldoutSize) * tan_half;
        return plane * std::sqrt(1.0f + sx * sx + sy * sy);
    });
    const RenderImage expected = renderScene(boxScene(half));
    const RenderImage full = renderScene(boxScene(box));
    const RenderImage cut_z = renderScene(heldOut(boxScene(box), dir + "/z.exr"));
    const RenderImage cut_distance = renderScene(heldOut(boxScene(box), dir + "/distance.exr", true));
    const float centre_alpha = expected.pixels[size_t(kHoldoutSize / 2 * kHoldoutSize + kHoldoutSize / 2)].rgba.w;
    EXPECT_GT(centre_alpha, 0.99f);   // 2 world units at 3 a unit
    EXPECT_GT(largestDifference(expected, full), 1e-3f);   // the back half shows through the edges
    std::printf("  cut at Z: %.2e from the half box; at ray distances: %.2e\n", double(largestDifference(expected, cut_z)),
                double(largestDifference(expected, cut_distance)));
    EXPECT_LE(largestDifference(expected, cut_z), 1e-4f);
    EXPECT_LE(largestDifference(expected, cut_distance), 1e-4f);
    EXPECT_LE(largestDifference(cut_z, cut_distance), 1e-5f);
}

// A new depth image (the next frame's, or the file edited) re-runs the holdouts and the march, not
// the lighting; the convention's flag the same.
TEST(Holdouts, ANewDepthImageRerunsTheHoldoutsAndTheMarchOnly) {
    const std::string dir = tempDir("holdout-rerun");
    const std::string box = writeBox(dir, "box.vdb", -20);
    writeDepthExr(dir + "/cg.exr", kHoldoutSize, kHoldoutSize, [](int, int) { return kCameraZ; });
    Scene scene = heldOut(boxScene(box), dir + "/cg.exr");
    scene.effects.shadows = ShadowMethod::Propagation;
    Renderer renderer(scene);
    const FrameResult first = renderer.render(std::nullopt, false);
    const auto ran = [](const FrameResult& r) {
        std::vector<std::string> names;
        for (const StageReport& s : r.stages)
            if (s.status == StageStatus::Ran) names.push_back(s.name);
        return names;
    };
    EXPECT_EQ(ran(renderer.render(std::nullopt, false)), std::vector<std::string>{});
    std::filesystem::remove(dir + "/cg.exr");
    writeDepthExr(dir + "/cg.exr", kHoldoutSize, kHoldoutSize, [](int x, int) { return x < kHoldoutSize / 2 ? 5.0f : 100.0f; });
    const FrameResult edited = renderer.render(std::nullopt, false);
    EXPECT_EQ(ran(edited), (std::vector<std::string>{"holdouts", "march"}));
    // The box spans pixels 4 to 15 of a row: held out on the left, seen on the right.
    EXPECT_EQ(edited.image.pixels[size_t(kHoldoutSize / 2 * kHoldoutSize + 5)].rgba.w, 0.0f);
    EXPECT_GT(edited.image.pixels[size_t(kHoldoutSize / 2 * kHoldoutSize + 14)].rgba.w, 0.9f);
    scene.holdouts[0].ray_distance = true;
    renderer.setScene(scene);
    EXPECT_EQ(ran(renderer.render(std::nullopt, false)), (std::vector<std::string>{"holdouts", "march"}));
}

// A render at a fraction of the depth image's size (the viewer's coarse levels) takes the nearest
// surface of each block; a depth image cropped to its data window (as renderers write to save
// space) is placed in its frame, with no surface outside the data window.
TEST(Holdouts, CoarseRendersTakeEachBlocksNearestAndCroppedImagesTheirFrame) {
    const std::string dir = tempDir("holdout-blocks");
    const std::string box = writeBox(dir, "box.vdb", -20);
    // Twice the render's size: one image pixel of each 2x2 block in front of the box, the rest behind.
    writeDepthExr(dir + "/fine.exr", 2 * kHoldoutSize, 2 * kHoldoutSize, [](int x, int y) { return x % 2 == 1 && y % 2 == 0 ? 5.0f : 100.0f; });
    for (const kernel::VxPixel& p : renderScene(heldOut(boxScene(box), dir + "/fine.exr")).pixels) ASSERT_EQ(p.rgba.w, 0.0f);
    // The left half of the frame in front of the box, the right half cropped away.
    {
        std::vector<float> values(size_t(kHoldoutSize / 2) * kHoldoutSize, 5.0f);
        Imf::Header header(Imath::Box2i({0, 0}, {kHoldoutSize - 1, kHoldoutSize - 1}), Imath::Box2i({0, 0}, {kHoldoutSize / 2 - 1, kHoldoutSize - 1}));
        header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer fb;
        fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), sizeof(float), sizeof(float) * size_t(kHoldoutSize / 2)));
        Imf::OutputFile file((dir + "/cropped.exr").c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(kHoldoutSize);
    }
    const RenderImage cut = renderScene(heldOut(boxScene(box), dir + "/cropped.exr")), open = renderScene(boxScene(box));
    for (int x = 0; x < kHoldoutSize; ++x) {
        const size_t i = size_t(kHoldoutSize / 2) * kHoldoutSize + size_t(x);
        if (x < kHoldoutSize / 2) EXPECT_EQ(cut.pixels[i].rgba.w, 0.0f) << x;
        else EXPECT_EQ(cut.pixels[i].rgba, open.pixels[i].rgba) << x;
    }
}

// Several volumes, lit by shadow rays, one of them glowing (the march's sample-by-sample path):
// cut through the box's middle, the scene renders as the one with the half box. The light comes
// from the camera's side, so the box's front half is lit alike in both, and the fire ball lies in
// front of the cut.
TEST(Holdouts, SeveralVolumesWithEmissionAndShadowsAreCutAlike) {
    const std::string dir = tempDir("holdout-several");
    const std::string box = writeBox(dir, "box.vdb", -20), half = writeBox(dir, "half.vdb", 1), fire = writeFireBall(dir);
    writeDepthExr(dir + "/z.exr", kHoldoutSize, kHoldoutSize, [](int, int) { return kCameraZ - 0.05f; });
    const auto scene = [&](const std::string& file) {
        Scene s = boxScene(file);
        s.effects.shadows = ShadowMethod::Raymarch;
        Light key;
        key.direction = glm::normalize(glm::vec3(0.2f, -0.1f, -1.0f));
        key.intensity = 2.0f;
        s.lights.push_back(key);
        VolumeSpec glow;
        glow.path = fire;
        glow.name = "fire";
        glow.transform = VolumeTransform{};
        glow.transform->translate = glm::vec3(2.0f, 0.0f, 3.5f);
        EmissionSource heat;
        heat.grid = GridRef{"heat", 0};
        heat.color = glm::vec3(1.0f, 0.45f, 0.1f);
        heat.intensity = 2.0f;
        glow.emission = {heat};
        s.volumes.push_back(glow);
        return s;
    };
    const RenderImage expected = renderScene(scene(half)), cut = renderScene(heldOut(scene(box), dir + "/z.exr"));
    float glowing = 0.0f;
    for (const auto& p : cut.pixels) glowing = std::max(glowing, glm::compMax(p.emission));
    EXPECT_GT(glowing, 0.1f);
    std::printf("  several volumes cut at Z: %.2e from the half box\n", double(largestDifference(expected, cut)));
    EXPECT_LE(largestDifference(expected, cut), 1e-4f);
}

TEST(Holdouts, GlCutsAsTheCpuDoesOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    const std::string dir = tempDir("holdout-gl");
    const std::string box = writeBox(dir, "box.vdb", -20);
    writeDepthExr(dir + "/slant.exr", kHoldoutSize, kHoldoutSize, [](int x, int) { return kCameraZ - 2.0f + 0.2f * float(x); });
    Scene scene = heldOut(boxScene(box), dir + "/slant.exr");
    const RenderImage cpu = renderScene(scene);
    scene.render.backend = Backend::Gl;
    EXPECT_LE(largestDifference(cpu, renderScene(scene)), 1e-4f);
}

TEST(Holdouts, BadDepthImagesAreRefusedByName) {
    const std::string dir = tempDir("holdout-bad");
    const std::string box = writeBox(dir, "box.vdb", -20);
    writeDepthExr(dir + "/small.exr", 8, 8, [](int, int) { return 1.0f; });
    writeDepthExr(dir + "/depth.exr", kHoldoutSize, kHoldoutSize, [](int, int) { return 1.0f; }, "depth.Z");
    EXPECT_EQ(inputErrorOf([&] { renderScene(heldOut(boxScene(box), dir + "/small.exr")); }),
              dir + "/small.exr: is 8x8, the render 20x20: a depth holdout is read pixel for pixel (or in whole blocks of pixels)");
    EXPECT_EQ(inputErrorOf([&] { renderScene(heldOut(boxScene(box), dir + "/depth.exr")); }), dir + "/depth.exr: no channel 'Z' (it has depth.Z)");
    EXPECT_EQ(inputErrorOf([&] { renderScene(heldOut(boxScene(box), dir + "/missing.exr")); }).rfind(dir + "/missing.exr: cannot read EXR (", 0), 0u);
    const std::string v = R"({"volume": {"path": "a.vdb"}, )";
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.obj"}]})"),
              "shot.json: /holdouts/0/mesh: mesh holdouts are not supported yet: give the CG render's depth image (\"depth\")");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"channel": "Z"}]})"), "shot.json: /holdouts/0/depth: required key is missing");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"depth": "cg.exr", "channel": ""}]})"), "shot.json: /holdouts/0/channel: must name a channel of the depth image");
}

}  // namespace
}  // namespace voxlux::test
