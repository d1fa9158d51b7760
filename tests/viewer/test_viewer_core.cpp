// The viewer's parts that need no window: the scene editor, the camera moves, the script reader,
// and the progressive render worker (its converged image is the Renderer's, newer edits cancel
// older ones, failures keep the last good image, and a light drag is a run of selective updates).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/error.h"
#include "io/png_writer.h"
#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"
#include "optics/environment_map.h"
#include "viewer/environment_thumbnail.h"
#include "viewer/orbit_camera.h"
#include "viewer/progressive_render.h"
#include "viewer/scene_editor.h"
#include "viewer/view_script.h"

namespace voxlux::test {
namespace {

const std::string kDefaultScene = sourceDir() + "/grids/default.json";

// The bundled cloud at a small size, trilinear, so a render takes milliseconds.
Scene smallCloud() {
    Scene s = loadSceneFile(kDefaultScene);
    s.render.width = 96;
    s.render.height = 60;
    s.render.filter = Filter::Trilinear;
    s.effects.light_resolution = 32;
    return s;
}

TEST(SceneEditor, ARefusedEditKeepsTheSceneAndSaysWhy) {
    SceneEditor editor(smallCloud());
    const uint64_t version = editor.version();
    EXPECT_FALSE(editor.set("material.density_scale=-1"));
    EXPECT_EQ(editor.error(), "set material.density_scale=-1: /volumes/0/material/density_scale: must be 0 or more");
    EXPECT_EQ(editor.version(), version);
    EXPECT_FLOAT_EQ(editor.scene().volume().material.density_scale, 40.0f);
    EXPECT_TRUE(editor.set("material.density_scale=20"));
    EXPECT_EQ(editor.error(), "");
    EXPECT_FLOAT_EQ(editor.scene().volume().material.density_scale, 20.0f);
    EXPECT_GT(editor.version(), version);
}

TEST(SceneEditor, SoloTwiceGivesEachLightItsStateBack) {   // a light's, and a light group's
    Scene s = smallCloud();
    s.lights.push_back(s.lights[0]);
    s.lights[2].name = "rim";
    s.lights[2].enabled = false;
    SceneEditor editor(s);
    ASSERT_TRUE(editor.soloLight(1));
    EXPECT_FALSE(editor.scene().lights[0].enabled);
    EXPECT_TRUE(editor.scene().lights[1].enabled);
    EXPECT_FALSE(editor.scene().lights[2].enabled);
    ASSERT_TRUE(editor.soloLight(1));
    EXPECT_TRUE(editor.scene().lights[0].enabled);
    EXPECT_TRUE(editor.scene().lights[1].enabled);
    EXPECT_FALSE(editor.scene().lights[2].enabled);
    EXPECT_EQ(editor.lightIndex("rim"), 2);
    // A light group's solo: its lights alone (the default group's, those that name none), and again
    // each light's state back; a group's name is set and cleared as a light's key.
    ASSERT_TRUE(editor.changeLight(1, {{"group", "key"}}));
    EXPECT_EQ(editor.scene().lights[1].group, "key");
    ASSERT_TRUE(editor.soloGroup(""));
    EXPECT_TRUE(editor.soloedGroup(""));
    EXPECT_TRUE(editor.scene().lights[0].enabled);
    EXPECT_FALSE(editor.scene().lights[1].enabled);
    EXPECT_TRUE(editor.scene().lights[2].enabled);
    ASSERT_TRUE(editor.soloGroup("key"));   // another solo keeps the states from before the first
    EXPECT_FALSE(editor.scene().lights[0].enabled);
    EXPECT_TRUE(editor.scene().lights[1].enabled);
    ASSERT_TRUE(editor.soloGroup("key"));
    EXPECT_TRUE(editor.scene().lights[0].enabled);
    EXPECT_TRUE(editor.scene().lights[1].enabled);
    EXPECT_FALSE(editor.scene().lights[2].enabled);
    ASSERT_TRUE(editor.changeLight(1, {{"group", nullptr}}));
    EXPECT_EQ(editor.scene().lights[1].group, "");
    EXPECT_EQ(inputErrorOf([&] { editor.lightIndex("fill"); }), "no light named \"fill\"");
    EXPECT_EQ(inputErrorOf([&] { editor.lightIndex(3); }), "no light 3 (the scene has 3)");
}

// Every edit but the camera's is an undo step; edits of one kind while a step is held (a drag)
// merge into one; undo and redo leave the camera where it is; a new edit drops what could be redone.
TEST(SceneEditor, UndoAndRedoStepThroughEditsAndLeaveTheCamera) {
    SceneEditor editor(smallCloud());
    const Scene start = editor.scene();
    EXPECT_FALSE(editor.undo());
    Light l = start.lights[0];
    editor.holdStep(true);   // a drag: three moves of the light, one step
    for (float x : {0.1f, 0.2f, 0.3f}) {
        l.direction.x = x;
        ASSERT_TRUE(editor.setLight(0, l));
    }
    editor.holdStep(false);
    const glm::vec3 dragged = editor.scene().lights[0].direction;   // as the scene keeps it: normalized
    ASSERT_TRUE(editor.set("material.anisotropy=0.5"));
    Camera moved;
    moved.position = glm::vec3(9.0f, 1.0f, 2.0f);
    ASSERT_TRUE(editor.setCamera(moved));
    EXPECT_EQ(editor.undoSteps(), 2u);
    ASSERT_TRUE(editor.undo());
    EXPECT_EQ(editor.scene().volume().material.anisotropy, start.volume().material.anisotropy);
    EXPECT_EQ(editor.scene().lights[0].direction, dragged);
    EXPECT_EQ(editor.scene().camera->position, moved.position);
    ASSERT_TRUE(editor.undo());
    EXPECT_EQ(editor.scene().lights[0].direction, start.lights[0].direction);
    EXPECT_EQ(editor.scene().camera->position, moved.position);
    EXPECT_FALSE(editor.undo());
    ASSERT_TRUE(editor.redo());
    EXPECT_EQ(editor.scene().lights[0].direction, dragged);
    ASSERT_TRUE(editor.redo());
    EXPECT_EQ(editor.scene().volume().material.anisotropy, 0.5f);
    EXPECT_FALSE(editor.redo());
    ASSERT_TRUE(editor.undo());
    ASSERT_TRUE(editor.set("material.anisotropy=0.2"));   // a new edit: nothing to redo
    EXPECT_FALSE(editor.redo());
    // Held, edits of another kind open a step of their own.
    editor.holdStep(true);
    ASSERT_TRUE(editor.set("material.anisotropy=0.3"));
    ASSERT_TRUE(editor.set("render.exposure=1"));
    ASSERT_TRUE(editor.set("render.exposure=2"));
    editor.holdStep(false);
    EXPECT_EQ(editor.undoSteps(), 4u);
}

TEST(SceneEditor, ATypeChangeDropsTheKeysTheNewTypeLacks) {
    SceneEditor editor(smallCloud());
    ASSERT_TRUE(editor.changeLight(0, {{"type", "point"}, {"position", {1, 2, 3}}}));
    const nlohmann::json light = editor.json()["lights"][0];
    EXPECT_FALSE(light.contains("direction"));
    EXPECT_EQ(light["position"], nlohmann::json({1.0, 2.0, 3.0}));
    EXPECT_EQ(editor.scene().lights[0].type, LightType::Point);
}

TEST(SceneEditor, ASavedSceneReadsBackTheSameFromAnotherFolder) {
    SceneEditor editor(smallCloud());
    const std::string path = tempDir("viewer-save") + "/nested/scene.json";
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    editor.save(path);
    const Scene back = loadSceneFile(path);
    EXPECT_EQ(std::filesystem::canonical(back.volume().path), std::filesystem::canonical(editor.scene().volume().path));
    nlohmann::json a = sceneToJson(back), b = editor.json();
    a["volumes"][0].erase("path");
    b["volumes"][0].erase("path");
    EXPECT_EQ(a, b);
}

// The thumbnail of a map black but for two grey pixels: the map's own size (it is under 256 x 128),
// one dot on each pixel for K = 2, each dot's share its pixel's radiance times solid angle over
// the two, the bright pixel white and the black ones black through the scene's view.
TEST(EnvironmentThumbnail, TheCutsDotsSitOnTheMapsPixelsWithTheirShareOfThePower) {
    constexpr int kW = 32, kH = 16;
    const glm::ivec2 a(5, 3), b(20, 10);
    const std::string map = writeMap(tempDir("thumbnail") + "/two.exr", kW, kH, [&](int x, int y) {
        return glm::vec3(glm::ivec2(x, y) == a ? 100.0f : glm::ivec2(x, y) == b ? 50.0f : 0.0f);
    });
    Scene scene;
    Light sky;
    sky.type = LightType::Environment;
    sky.enabled = false;   // a thumbnail all the same
    sky.environment = EnvironmentSettings{};
    sky.environment->map = map;
    sky.environment->up = glm::vec3(0, 0, 1);
    sky.environment->rotation = 70.0f;   // the file's layout all the same
    sky.environment->median_cut_lights = 2;
    sky.environment->remainder = EnvironmentRemainder::None;
    scene.lights = {sky};
    const EnvironmentThumbnail t = environmentThumbnail(scene, 0);
    ASSERT_EQ(t.width, kW);
    ASSERT_EQ(t.height, kH);
    ASSERT_EQ(t.cut.size(), 2u);
    const EnvironmentMap frame(kW, kH, std::vector<glm::vec3>(kW * kH), glm::vec3(0, 0, 1), 0.0f);
    const double power_a = 100.0 * frame.pixelSolidAngle(a.y), power_b = 50.0 * frame.pixelSolidAngle(b.y);
    for (const auto& p : t.cut) {
        const glm::ivec2 pixel(p.uv * glm::vec2(kW, kH));
        ASSERT_TRUE(pixel == a || pixel == b) << pixel.x << " " << pixel.y;
        EXPECT_NEAR(p.share, (pixel == a ? power_a : power_b) / (power_a + power_b), 1e-5);
    }
    EXPECT_NE(t.cut[0].uv, t.cut[1].uv);
    const auto red = [&](glm::ivec2 p) { return int(t.texels[(size_t(p.y) * kW + p.x) * 4]); };
    EXPECT_EQ(red(a), 255);
    EXPECT_EQ(red({0, 0}), 0);
}

TEST(OrbitCamera, OrbitKeepsTheDistanceAndStopsShortOfThePole) {
    Camera c;
    c.position = {0, 0, 5};
    c.look_at = {0, 0, 0};
    const Camera yawed = orbit(c, 90.0f, 0.0f);
    EXPECT_NEAR(yawed.position.x, 5.0f, 1e-5f);
    EXPECT_NEAR(yawed.position.z, 0.0f, 1e-5f);
    const Camera over = orbit(c, 0.0f, 120.0f);   // asks past the pole
    EXPECT_NEAR(glm::length(over.position), 5.0f, 1e-4f);
    EXPECT_NEAR(glm::degrees(std::asin(over.position.y / 5.0f)), 89.0f, 1e-3f);
}

TEST(OrbitCamera, PanMovesBothPointsAndDollyScalesTheDistance) {
    Camera c;
    c.position = {0, 0, 4};
    c.look_at = {0, 0, 0};
    c.fov = 90.0f;   // the view is 2 x 4 = 8 high at the look-at point
    const Camera p = pan(c, {0.25f, 0.0f});
    EXPECT_NEAR(p.look_at.x, 2.0f, 1e-5f);
    EXPECT_NEAR(p.position.x, 2.0f, 1e-5f);
    EXPECT_NEAR(glm::length(dolly(c, 0.5f).position), 2.0f, 1e-6f);
}

TEST(OrbitCamera, FrameFitsTheBoxesSphereAndProjectsItsCentreToTheMiddle) {
    Camera c;
    c.position = {0, 0, 10};
    c.look_at = {0, 0, 9};
    c.fov = 60.0f;
    const Camera f = frameAlong(c, glm::vec3(1, 1, 1), glm::vec3(3, 3, 3));
    EXPECT_EQ(f.look_at, glm::vec3(2, 2, 2));
    EXPECT_NEAR(glm::length(f.position - f.look_at), std::sqrt(3.0f) / std::sin(glm::radians(30.0f)), 1e-4f);
    glm::vec2 px;
    ASSERT_TRUE(projectToImage(f, {200, 100}, f.look_at, px));
    EXPECT_NEAR(px.x, 100.0f, 1e-3f);
    EXPECT_NEAR(px.y, 50.0f, 1e-3f);
    EXPECT_FALSE(projectToImage(f, {200, 100}, f.position + (f.position - f.look_at), px));
}

TEST(ViewScript, BadActionsNameTheFileAndTheAction) {
    const auto error = [](const std::string& text) { return inputErrorOf([&] { parseViewScript(text, "s.json"); }); };
    EXPECT_EQ(error(R"({"edits": []})"), "s.json: a view script is an object with an \"actions\" array");
    EXPECT_EQ(error(R"({"actions": [{"jump": 1}]})"), "s.json: /actions/0: unknown action \"jump\"");
    EXPECT_EQ(error(R"({"actions": [{"orbit": [1]}]})"), "s.json: /actions/0/orbit: must be two numbers");
    EXPECT_EQ(error(R"({"actions": [{"wait": "forever"}]})"), "s.json: /actions/0/wait: must be \"converged\" or seconds");
    EXPECT_EQ(error(R"({"actions": [{"light": "sun"}]})"), "s.json: /actions/0: a light action needs \"set\": an object of the light's keys");
    EXPECT_EQ(error(R"({"actions": [{"quit": true, "now": 1}]})"), "s.json: /actions/0/now: unknown key (expected one of quit)");
    EXPECT_EQ(parseViewScript(R"({"actions": [{"light": 0, "set": {"intensity": 2}}, {"wait": 0.5}]})", "s.json").size(), 2u);
}

// The image `voxlux render --preview` makes of `scene`.
FrameResult renderOnce(Scene scene) {
    if (scene.output.preview.empty()) scene.output.preview = "unused.png";
    Renderer renderer(scene);
    return renderer.render(std::nullopt, true);
}

// Equal images, or within `tolerance` of each other (relative to the brighter, per channel).
void expectSameImage(const ViewFrame& shown, const FrameResult& rendered, float tolerance = 0.0f) {
    ASSERT_EQ(shown.display.size(), rendered.preview.size());
    ASSERT_EQ(shown.image.pixels.size(), rendered.image.pixels.size());
    const auto near = [tolerance](glm::vec4 a, glm::vec4 b) {
        return glm::all(glm::lessThanEqual(glm::abs(a - b), tolerance * glm::max(glm::abs(a), glm::abs(b))));
    };
    for (size_t i = 0; i < shown.display.size(); ++i) {
        ASSERT_TRUE(near(shown.display[i], rendered.preview[i])) << "pixel " << i;
        ASSERT_TRUE(near(shown.image.pixels[i].rgba, rendered.image.pixels[i].rgba)) << "pixel " << i;
    }
}

// The viewport's texels round as the PNG preview does (std::lround of the clamped value), over
// every 8-bit step and its edges, and show non-finite values black.
TEST(ProgressiveRender, TexelsRoundAsThePngPreview) {
    std::vector<glm::vec4> display;
    for (int k = -2; k <= 257 * 8; ++k) {
        const float v = k / (255.0f * 8.0f);
        display.push_back(glm::vec4(v, std::nextafter(v, 2.0f), std::nextafter(v, -1.0f), 0.0f));
    }
    display.push_back(glm::vec4(NAN, INFINITY, -INFINITY, NAN));
    const std::vector<uint8_t> texels = opaqueTexels(display);
    ASSERT_EQ(texels.size(), display.size() * 4);
    for (size_t i = 0; i + 1 < display.size(); ++i)
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(int(texels[i * 4 + c]), int(std::lround(std::clamp(display[i][c], 0.0f, 1.0f) * 255.0f))) << display[i][c];
    EXPECT_EQ(int(texels[3]), 255);
    const size_t last = (display.size() - 1) * 4;
    EXPECT_EQ(std::vector<uint8_t>(texels.begin() + last, texels.end()), (std::vector<uint8_t>{0, 0, 0, 255}));
}

TEST(ProgressiveRender, TheConvergedImageIsTheRenderersAfterCoarserLevels) {
    const Scene scene = smallCloud();
    ProgressiveRender view(scene, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    const auto shown = view.latest();
    ASSERT_TRUE(shown);
    EXPECT_TRUE(shown->converged);
    EXPECT_EQ(shown->levels, 2);   // 96 wide: 1/2 (48) and full; 1/4 and 1/8 are under 32 pixels
    EXPECT_EQ(shown->level, 1);
    EXPECT_EQ(levelResolution({96, 60}, 8), glm::ivec2(12, 8));
    expectSameImage(*shown, renderOnce(scene));
}

TEST(ProgressiveRender, TheReferenceAddsSamplesUntilItIsTheRenderersImage) {
    Scene scene = smallCloud();
    scene.render.width = 48;
    scene.render.height = 30;
    scene.render.method = RenderMethod::Reference;
    scene.render.reference.spp = 6;
    scene.effects.shadows = ShadowMethod::Raymarch;
    scene.effects.indirect.reset();
    scene.effects.ambient_occlusion.reset();
    const std::vector<ViewLevel> levels = progressiveLevels(scene);   // 48 wide: no coarser level
    ASSERT_EQ(levels.size(), 4u);
    EXPECT_EQ(levels[0].samples, 1);
    EXPECT_EQ(levels[1].samples, 2);
    EXPECT_EQ(levels[2].samples, 4);
    EXPECT_EQ(levels[3].samples, 6);
    ProgressiveRender view(scene, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    EXPECT_EQ(view.latest()->samples, 6);
    // Samples 4 and 5 were added to the sums of 0-3: the image is the one-go render's, bit for bit.
    expectSameImage(*view.latest(), renderOnce(scene));
}

TEST(ProgressiveRender, MoreReferenceSamplesAreAddedToTheLastOnes) {
    Scene scene = smallCloud();
    scene.render.method = RenderMethod::Reference;
    scene.render.reference.spp = 4;
    scene.effects.shadows = ShadowMethod::Raymarch;
    scene.effects.indirect.reset();
    scene.effects.ambient_occlusion.reset();
    Renderer renderer(scene);
    renderer.keepReferenceSums(true);
    renderer.render(std::nullopt, true);
    scene.render.reference.spp = 6;
    renderer.setScene(scene);
    const FrameResult more = renderer.render(std::nullopt, true);
    EXPECT_NE(std::find(more.reused.begin(), more.reused.end(), "march: 4 reference samples a pixel"), more.reused.end());
    const FrameResult fresh = renderOnce(scene);
    for (size_t i = 0; i < fresh.image.pixels.size(); ++i) ASSERT_EQ(more.image.pixels[i].rgba, fresh.image.pixels[i].rgba) << i;
    // Anything else changed (here the seed) starts the sums again.
    scene.render.reference.seed = 2;
    scene.render.reference.spp = 8;
    renderer.setScene(scene);
    const FrameResult reseeded = renderer.render(std::nullopt, true);
    EXPECT_EQ(std::count_if(reseeded.reused.begin(), reseeded.reused.end(), [](const std::string& r) { return r.rfind("march:", 0) == 0; }), 0);
}

TEST(ProgressiveRender, TheNewestOfManyEditsWins) {
    Scene scene = smallCloud();
    ProgressiveRender view(scene, std::nullopt);
    uint64_t last = 0;
    for (int k = 0; k < 12; ++k) {
        scene.volume().material.anisotropy = 0.02f * float(k);
        last = view.submit(scene, std::nullopt);
    }
    ASSERT_TRUE(view.waitConverged(120.0));
    EXPECT_EQ(view.latest()->edit, last);
    const ViewStatistics st = view.statistics();
    EXPECT_EQ(st.submitted, 13u);
    EXPECT_LT(st.converged, 13u);   // coalesced: most edits never rendered
    expectSameImage(*view.latest(), renderOnce(scene));
}

TEST(ProgressiveRender, AnEditDuringAMarchCancelsItAndRendersNext) {
    Scene scene = smallCloud();
    scene.render.width = 480;   // a full-resolution march long enough to be cut short
    scene.render.height = 300;
    scene.render.filter = Filter::Tricubic;
    ProgressiveRender view(scene, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    uint64_t last = 0;
    for (int k = 0; k < 3; ++k) {
        scene.volume().material.anisotropy = 0.1f * float(k);
        last = view.submit(scene, std::nullopt);
        // As soon as this edit's coarsest image shows, the next edit lands on its finer marches.
        for (int wait = 0; wait < 20000 && view.latest()->edit != last; ++wait) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(view.waitConverged(120.0));
    EXPECT_FALSE(view.failure()) << view.failure()->message;
    EXPECT_GE(view.statistics().cancelled, 1u);
    EXPECT_EQ(view.latest()->edit, last);
    expectSameImage(*view.latest(), renderOnce(scene));
}

TEST(ProgressiveRender, AFailedEditSaysWhyAndTheLastGoodSceneShowsAgain) {
    const Scene good = smallCloud();
    ProgressiveRender view(good, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    Scene bad = good;
    bad.volume().path = tempDir("viewer-missing") + "/gone.vdb";
    const uint64_t edit = view.submit(bad, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    const auto failure = view.failure();
    ASSERT_TRUE(failure);
    EXPECT_EQ(failure->edit, edit);
    EXPECT_EQ(failure->message, bad.volume().path + ": no such file");
    EXPECT_EQ(failure->last_good.volume().path, good.volume().path);
    EXPECT_GT(view.latest()->edit, edit);   // the last good scene rendered again
    expectSameImage(*view.latest(), renderOnce(good));
}

TEST(ProgressiveRender, WhenTheLastGoodSceneFailsTooTheFailureStands) {
    Scene good = smallCloud();
    const std::string copy = tempDir("viewer-removed") + "/cloud.vdb";
    std::filesystem::copy_file(good.volume().path, copy, std::filesystem::copy_options::overwrite_existing);
    good.volume().path = copy;
    ProgressiveRender view(good, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    std::filesystem::remove(copy);   // gone since it rendered: the re-render of the last good scene fails too
    Scene bad = good;
    bad.volume().path = copy + ".missing";
    view.submit(bad, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    const auto failure = view.failure();
    ASSERT_TRUE(failure);
    EXPECT_EQ(failure->message, copy + ": no such file");
    EXPECT_FALSE(failure->restored);   // no second restore: the worker is idle, not looping
    EXPECT_EQ(view.statistics().submitted, 2u);
    EXPECT_TRUE(view.settled());
}

// Scrubbing back to a frame takes its grids and bricks from the frame cache, and the viewer says so.
// A mesh holdout over the view's left part, in front of the cloud: there the viewport shows the
// dark grey silhouette (the render's alpha is 0 there), elsewhere the render as it is.
TEST(ProgressiveRender, HoldoutsShowAsDarkSilhouettes) {
    const std::string dir = tempDir("viewer-holdout");
    std::ofstream(dir + "/wall.obj") << "v -5 -5 2.5\nv 0.1 -5 2.5\nv 0.1 5 2.5\nv -5 5 2.5\nf 1 2 3 4\n";
    Scene scene = smallCloud();
    Holdout wall;
    wall.mesh = dir + "/wall.obj";
    scene.holdouts = {wall};
    ProgressiveRender view(scene, 1, size_t(256) << 20);
    ASSERT_TRUE(view.waitConverged(120.0));
    const auto shown = view.latest();
    const auto texel = [&](int x, int y) { return shown->display_texels[(size_t(y) * 96 + size_t(x)) * 4]; };
    EXPECT_EQ(shown->display[size_t(30) * 96 + 2].w, 0.0f);
    EXPECT_EQ(texel(2, 30), displayByte(kHoldoutGrey));
    EXPECT_EQ(texel(93, 2), 0);   // neither cloud nor wall
    const size_t cloud = size_t(30) * 96 + 70;   // right of the wall: the render as it is
    EXPECT_GT(shown->display[cloud].w, 0.5f);
    EXPECT_EQ(texel(70, 30), displayByte(shown->display[cloud].x));
}

TEST(ProgressiveRender, ScrubbingBackToAFrameTakesItsBricksFromTheCache) {
    const std::string dir = tempDir("viewer-frames");
    std::filesystem::copy_file(smallCloud().volume().path, dir + "/cloud_0001.vdb", std::filesystem::copy_options::overwrite_existing);
    openvdb::io::File(dir + "/cloud_0002.vdb").write({boxGrid({-20, -20, -20}, {20, 20, 20}, 1.0f, 0.02)});
    Scene scene = smallCloud();
    scene.volume().path = dir + "/cloud_####.vdb";
    scene.volume().frames = FrameSet(1, 2);
    ProgressiveRender view(scene, 1, size_t(256) << 20);
    ASSERT_TRUE(view.waitConverged(120.0));
    const std::vector<glm::vec4> first = view.latest()->display;
    view.submit(scene, 2);
    ASSERT_TRUE(view.waitConverged(120.0));
    EXPECT_NE(view.latest()->display, first);   // a box, not the cloud
    view.submit(scene, 1);
    ASSERT_TRUE(view.waitConverged(120.0));
    const auto shown = view.latest();
    std::vector<std::string> cached;
    for (const StageReport& s : shown->edit_stages)
        if (s.cached) cached.push_back(s.name);
    EXPECT_EQ(cached, (std::vector<std::string>{"load", "brick"}));
    EXPECT_EQ(shown->cache_outputs, 4u);
    EXPECT_GT(shown->cache_bytes, 0u);
    EXPECT_EQ(shown->display, first);
}

TEST(ProgressiveRender, DraggingOneOfSeveralLightsIsSelectiveUpdates) {
    Scene scene = smallCloud();
    scene.effects.indirect.reset();
    for (int k = 0; k < 3; ++k) {   // three more keys, along other axes
        Light l = scene.lights[0];
        l.name = "key" + std::to_string(k);
        l.direction = glm::normalize(glm::vec3(k == 0, k == 1 ? -1 : 0.2f, k == 2));
        scene.lights.push_back(l);
    }
    ProgressiveRender view(scene, std::nullopt);
    ASSERT_TRUE(view.waitConverged(120.0));
    for (int k = 0; k < 4; ++k) {
        scene.lights[0].direction = glm::normalize(scene.lights[0].direction + glm::vec3(0.05f, 0, 0));
        view.submit(scene, std::nullopt);
        ASSERT_TRUE(view.waitConverged(120.0));
        ASSERT_TRUE(view.latest()->light_update);
        EXPECT_EQ(view.latest()->light_update->mode, LightUpdate::Mode::Selective) << view.latest()->light_update->reason;
        EXPECT_EQ(view.latest()->light_update->lights_out, 1);
        EXPECT_EQ(view.latest()->light_update->lights_in, 1);
    }
    const ViewStatistics st = view.statistics();
    EXPECT_EQ(st.entire_updates, 1u);   // the first image
    EXPECT_EQ(st.selective_updates, 4u);
    // Lights taken out and put back leave float residue (kDriftBudget), far below a display step.
    expectSameImage(*view.latest(), renderOnce(scene), 1e-4f);
}

}  // namespace
}  // namespace voxlux::test
