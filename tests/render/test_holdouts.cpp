// Holdouts (scene key `holdouts`, src/render/holdout_stage.h). Depth images: a surface behind the
// medium leaves the image bit for bit, one in front of it leaves nothing, one through the middle
// cuts the rays as a medium that ends there does; ray distances are camera-space Z over the ray's
// cosine; the reference and the GL backend cut as the CPU march does; bad depth images are refused
// by name. Meshes: a mesh cuts as the depth image of its surface does, shadows the medium in every
// method through its cells, follows its frame's file and its keys, and bad meshes are refused.
#include <filesystem>
#include <fstream>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <glm/gtx/component_wise.hpp>

#include "core/error.h"
#include "render/renderer.h"
#include "scene/camera.h"
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
    Holdout h;
    h.depth = depth;
    h.ray_distance = ray_distance;
    s.holdouts = {h};
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
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"channel": "Z"}]})"),
              "shot.json: /holdouts/0/depth: a holdout needs a depth image (\"depth\") or a mesh (\"mesh\")");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"depth": "cg.exr", "channel": ""}]})"), "shot.json: /holdouts/0/channel: must name a channel of the depth image");
}


// A rectangle of the plane `axis` = `at` over [lo, hi] in the other two axes, as an OBJ quad.
void writeQuad(const std::string& path, int axis, float at, glm::vec2 lo, glm::vec2 hi) {
    std::ofstream obj(path);
    for (const glm::vec2 c : {lo, glm::vec2(hi.x, lo.y), hi, glm::vec2(lo.x, hi.y)}) {
        glm::vec3 p;
        p[axis] = at, p[(axis + 1) % 3] = c.x, p[(axis + 2) % 3] = c.y;
        obj << "v " << p.x << " " << p.y << " " << p.z << "\n";
    }
    obj << "f 1 2 3 4\n";
}

Scene meshHeldOut(Scene s, const std::string& mesh) {
    Holdout h;
    h.mesh = mesh;
    s.holdouts.push_back(h);
    return s;
}

// A triangle far above the box, past its cells' reach and out of view: a scene with it renders
// through the march of several volumes (the mesh's cells are a volume) with nothing cut or shadowed,
// the baseline a mesh's effect is measured against.
std::string writeFarTriangle(const std::string& dir) {
    std::ofstream(dir + "/far.obj") << "v 0 100 0\nv 1 100 0\nv 0 100 1\nf 1 2 3\n";
    return dir + "/far.obj";
}

// The left half of the view (x < 0) held out at world z 1.7 (0.3 into the box) by a quad, and by
// the depth image of that quad (camera-space Z 10.3 in the left half's pixels, none in the
// right's): the same image, the cells the quad adds (which only shadow) changing nothing under an
// unoccluded ambient light.
TEST(Holdouts, AMeshCutsAsTheDepthImageOfItsSurfaceDoes) {
    const std::string dir = tempDir("holdout-mesh-cut");
    const std::string box = writeBox(dir, "box.vdb", -20);
    writeQuad(dir + "/half.obj", 2, 1.7f, {-5.0f, -5.0f}, {0.0f, 5.0f});
    writeDepthExr(dir + "/half.exr", kHoldoutSize, kHoldoutSize, [](int x, int) { return x < kHoldoutSize / 2 ? kCameraZ - 1.7f : 0.0f; });
    const std::string far = writeFarTriangle(dir);
    const RenderImage by_image = renderScene(meshHeldOut(heldOut(boxScene(box), dir + "/half.exr"), far));
    const RenderImage by_mesh = renderScene(meshHeldOut(boxScene(box), dir + "/half.obj"));
    const RenderImage open = renderScene(meshHeldOut(boxScene(box), far));
    EXPECT_GT(largestDifference(open, by_image), 0.1f);   // the cut shows
    std::printf("  mesh against its depth image: %.2e\n", double(largestDifference(by_image, by_mesh)));
    EXPECT_LE(largestDifference(by_image, by_mesh), 1e-5f);
    // The cells are the CG's: the coverage AOV has the box's channel alone.
    Scene written = meshHeldOut(boxScene(box), dir + "/half.obj");
    written.volumes[0].name = "box";
    written.output.path = dir + "/held.exr";
    written.output.aovs = {{"coverage", std::nullopt}};
    Renderer(written).renderToFile(std::nullopt, false);
    EXPECT_EQ(readExr(dir + "/held.exr").channels, (std::vector<std::string>{"A", "B", "G", "R", "coverage.box"}));
    // A quad over the left half in front of the medium: alpha 0 there, and on the right the image
    // without any holdout, to 1e-4: its cells make the render the march of several volumes, whose
    // resampling of the box differs from the one volume's by that much (as a matte's test finds in
    // tests/render/test_several_volumes.cpp).
    writeQuad(dir + "/left.obj", 2, 5.0f, {-5.0f, -5.0f}, {0.0f, 5.0f});
    const RenderImage left = renderScene(meshHeldOut(boxScene(box), dir + "/left.obj")), plain = renderScene(boxScene(box));
    float right_difference = 0.0f;
    for (int y = 0; y < kHoldoutSize; ++y)
        for (int x = 0; x < kHoldoutSize; ++x) {
            const size_t i = size_t(y) * kHoldoutSize + x;
            if (x < kHoldoutSize / 2) ASSERT_EQ(left.pixels[i].rgba, glm::vec4(0.0f)) << x << " " << y;
            else right_difference = std::max(right_difference, glm::compMax(glm::abs(left.pixels[i].rgba - plain.pixels[i].rgba)));
        }
    std::printf("  right of the quad against no holdout: %.2e\n", double(right_difference));
    EXPECT_LE(right_difference, 1e-4f);
    // In front of the medium, in the march and the reference alike: nothing at all.
    writeQuad(dir + "/wall.obj", 2, 5.0f, {-5.0f, -5.0f}, {5.0f, 5.0f});
    for (RenderMethod method : {RenderMethod::March, RenderMethod::Reference}) {
        Scene scene = meshHeldOut(boxScene(box), dir + "/wall.obj");
        scene.render.method = method;
        scene.render.reference.spp = 4;
        for (const kernel::VxPixel& p : renderScene(scene).pixels) {
            ASSERT_EQ(p.rgba, glm::vec4(0.0f));
            ASSERT_EQ(p.transmittance, 1.0f);
        }
    }
}

// The box lit straight from above, a quad inside it at y 1.5 over its left half (x < 0): below the
// quad the medium is in its shadow in every method and the reference, beside it lit as with the quad out of the way
// (writeFarTriangle). The pixels compared look at the box's front below y 1.2 and 0.4 units or
// more from x 0, away from the edge the cones soften and the light grid's cells straddle.
TEST(Holdouts, AMeshShadowsTheMediumInEveryMethod) {
    const std::string dir = tempDir("holdout-mesh-shadow");
    const std::string box = writeBox(dir, "box.vdb", -20), far = writeFarTriangle(dir);
    writeQuad(dir + "/shelf.obj", 1, 1.5f, {-2.5f, -5.0f}, {2.5f, 0.0f});   // (z, x): x over [-5, 0]
    const auto region = [](const RenderImage& image, bool left) {
        double sum = 0.0;
        int n = 0;
        const float tan_half = std::tan(glm::radians(15.0f));
        for (int y = 0; y < kHoldoutSize; ++y)
            for (int x = 0; x < kHoldoutSize; ++x) {
                const float sx = (2.0f * (float(x) + 0.5f) / kHoldoutSize - 1.0f) * tan_half;
                const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / kHoldoutSize) * tan_half;
                const float at_x = sx * (kCameraZ - 2.0f), at_y = sy * (kCameraZ - 2.0f);   // on the box's front face
                if (at_y > 1.2f || (left ? at_x > -0.4f : at_x < 0.4f)) continue;
                sum += luminance(image.pixels[size_t(y) * kHoldoutSize + x].direct);
                ++n;
            }
        return sum / n;
    };
    // The three methods of the march, then the reference's single scattering (its direct light).
    for (int method = 0; method < 4; ++method) {
        SCOPED_TRACE(method);
        Scene scene = boxScene(box);
        const ShadowMethod methods[] = {ShadowMethod::Raymarch, ShadowMethod::SatCone, ShadowMethod::Propagation, ShadowMethod::Raymarch};
        scene.effects.shadows = methods[method];
        if (method == 3) {
            scene.render.method = RenderMethod::Reference;
            scene.render.reference.spp = 512;
            scene.render.reference.max_bounces = 1;
        }
        Light sun;
        sun.direction = glm::vec3(0.0f, -1.0f, 0.0f);
        sun.intensity = 20.0f;
        scene.lights = {sun};
        const RenderImage open = renderScene(meshHeldOut(scene, far)), shaded = renderScene(meshHeldOut(scene, dir + "/shelf.obj"));
        const double lit = region(open, true), beside = region(shaded, false), under = region(shaded, true);
        const char* names[] = {"raymarch", "sat_cone", "propagation", "reference"};
        std::printf("  %s: lit %.4f (right %.4f), beside the shelf %.4f, under it %.2e\n", names[method], lit, region(open, false), beside, under);
        EXPECT_GT(lit, 0.01);
        // The reference's paths differ once the cells are there (its majorant does): its noise.
        EXPECT_NEAR(beside, region(open, false), (method == 3 ? 0.05 : 0.02) * lit);
        EXPECT_LT(under, 1e-3 * lit);
    }
}

// Without a scene camera, a mesh holdout leaves the framing of the volume alone (its cells are the
// CG's, not a volume to frame).
TEST(Holdouts, AMeshLeavesTheDefaultFraming) {
    const std::string dir = tempDir("holdout-mesh-framing");
    Scene scene = boxScene(writeBox(dir, "box.vdb", -20));
    scene.camera.reset();
    writeQuad(dir + "/wide.obj", 1, 0.0f, {-30.0f, -30.0f}, {30.0f, 30.0f});
    const Camera alone = Renderer(scene).render(std::nullopt, false).camera;
    const Camera held = Renderer(meshHeldOut(scene, dir + "/wide.obj")).render(std::nullopt, false).camera;
    EXPECT_EQ(test::largestDifference(cameraToWorld(alone), cameraToWorld(held)), 0.0f);
    EXPECT_EQ(alone.fov, held.fov);
}

// set.####.obj: each frame its own mesh (here the quad over the left half, then over the right);
// a keyed transform moves it between frames. Moving the mesh, or coarsening its cells, re-reads no
// file.
TEST(Holdouts, AMeshFollowsItsFramesFileAndItsKeys) {
    const std::string dir = tempDir("holdout-mesh-frames");
    const std::string box = writeBox(dir, "box.vdb", -20);
    writeQuad(dir + "/cg.0001.obj", 2, 5.0f, {-5.0f, -5.0f}, {0.0f, 5.0f});
    writeQuad(dir + "/cg.0002.obj", 2, 5.0f, {0.0f, -5.0f}, {5.0f, 5.0f});
    Scene scene = meshHeldOut(boxScene(box), dir + "/cg.####.obj");
    const auto cutHalf = [](const RenderImage& image) {   // -1: the left half is cut, 1: the right, 0: neither or both
        const auto& left = image.pixels[size_t(kHoldoutSize / 2) * kHoldoutSize + 2], right = image.pixels[size_t(kHoldoutSize / 2) * kHoldoutSize + 17];
        return (left.rgba.w == 0.0f ? -1 : 0) + (right.rgba.w == 0.0f ? 1 : 0);
    };
    Renderer renderer(scene);
    EXPECT_EQ(cutHalf(renderer.render(1, false).image), -1);
    EXPECT_EQ(cutHalf(renderer.render(2, false).image), 1);
    // Frame 1's quad moved right by 5 units at frame 1, by none at frame 3 (and 2.5 at frame 2).
    scene.holdouts[0].mesh = dir + "/cg.0001.obj";
    scene.holdouts[0].transform = VolumeTransform{};
    TransformKey moved, home;
    moved.frame = 1, moved.translate = glm::vec3(5.0f, 0.0f, 0.0f);
    home.frame = 3;
    scene.holdouts[0].transform->keys = {moved, home};
    renderer.setScene(scene);
    EXPECT_EQ(cutHalf(renderer.render(1, false).image), 1);
    const FrameResult later = renderer.render(3, false);
    EXPECT_EQ(cutHalf(later.image), -1);
    EXPECT_NE(std::find(later.reused.begin(), later.reused.end(), "holdout_meshes"), later.reused.end());   // kept whole
    // Coarser cells: the holdout's key changed, its file did not.
    scene.holdouts[0].voxel_size = 0.2f;
    renderer.setScene(scene);
    const FrameResult coarser = renderer.render(3, false);
    EXPECT_NE(std::find(coarser.reused.begin(), coarser.reused.end(), "holdout_meshes: " + dir + "/cg.0001.obj"), coarser.reused.end());
}

TEST(Holdouts, BadMeshesAreRefusedByName) {
    const std::string dir = tempDir("holdout-mesh-bad");
    const std::string box = writeBox(dir, "box.vdb", -20);
    std::ofstream(dir + "/points.obj") << "v 0 0 0\nv 1 0 0\n";
    std::ofstream(dir + "/broken.gltf") << "{\"asset\": ";
    EXPECT_EQ(inputErrorOf([&] { renderScene(meshHeldOut(boxScene(box), dir + "/missing.obj")); }), dir + "/missing.obj: cannot open mesh file");
    EXPECT_EQ(inputErrorOf([&] { renderScene(meshHeldOut(boxScene(box), dir + "/points.obj")); }), dir + "/points.obj: has no triangles");
    EXPECT_EQ(inputErrorOf([&] { renderScene(meshHeldOut(boxScene(box), dir + "/broken.gltf")); }).rfind(dir + "/broken.gltf: not a .gltf file assimp reads (", 0), 0u);
    const std::string v = R"({"volume": {"path": "a.vdb"}, )";
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.abc"}]})"),
              "shot.json: /holdouts/0/mesh: not a mesh file voxlux reads (expected .obj, .gltf, .glb or .fbx)");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.obj", "depth": "cg.exr"}]})"),
              "shot.json: /holdouts/0/depth: a holdout is a depth image or a mesh, not both");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.obj", "channel": "Z"}]})"), "shot.json: /holdouts/0/channel: unknown key (expected one of mesh, transform, voxel_size, shadow_reach)");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.obj", "voxel_size": -1}]})"),
              "shot.json: /holdouts/0/voxel_size: must be a finite length >= 0 in world units (0: the volumes' finest voxel)");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.obj", "shadow_reach": -1}]})"),
              "shot.json: /holdouts/0/shadow_reach: must be a finite length >= 0 in world units");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.obj"}], "output": {"path": "a.exr", "deep": true}})"),
              "shot.json: /output: deep output with a mesh holdout: its shadowing cells are a shadow_only volume, whose opacity the deep "
              "samples would carry, so far; hold the deep render out with the mesh's depth image");
    EXPECT_EQ(sceneErrorOf(v + R"("holdouts": [{"mesh": "set.obj"}], "effects": {"surface": true}})"),
              "shot.json: /effects/surface: set with a mesh holdout: its shadowing cells make the scene one of several volumes, which render "
              "without it, so far");
}

TEST(Holdouts, AMeshCutsAndShadowsOnGlAsOnTheCpuOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    const std::string dir = tempDir("holdout-mesh-gl");
    const std::string box = writeBox(dir, "box.vdb", -20);
    std::ofstream(dir + "/tilted.obj") << "v -5 -1 5\nv 0 1.5 -5\nv 0 1.5 5\nf 1 2 3\n";
    Scene scene = meshHeldOut(boxScene(box), dir + "/tilted.obj");
    scene.effects.shadows = ShadowMethod::SatCone;
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.2f));
    scene.lights.push_back(sun);
    const RenderImage cpu = renderScene(scene);
    scene.render.backend = Backend::Gl;
    EXPECT_LE(largestDifference(cpu, renderScene(scene)), 1e-4f);
}

}  // namespace
}  // namespace voxlux::test
