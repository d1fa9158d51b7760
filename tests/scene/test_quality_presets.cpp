// --quality: each preset gives a valid scene with its method, keeps what the scene says of an
// effect it turns on, yields to the other options, and an unknown name is one line.
#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/quality_presets.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux {
namespace {

Scene withPreset(const nlohmann::json& scene, const std::string& preset) {
    nlohmann::json j = scene;
    applyQualityPreset(j, preset);
    return parseScene(j.dump(), "shot.json", "");
}

nlohmann::json litScene() {
    return {{"volume", {{"path", "/shots/smoke.vdb"}}},
            {"lights", {{{"type", "directional"}, {"direction", {0, -1, 0}}}, {{"type", "ambient"}, {"intensity", 0.3}}}}};
}

TEST(QualityPresets, EachPresetPicksItsMethodAndKnobs) {
    const Scene draft = withPreset(litScene(), "draft");
    EXPECT_EQ(draft.render.method, RenderMethod::March);
    EXPECT_EQ(draft.render.step, 1.0f);
    EXPECT_EQ(draft.effects.shadows, ShadowMethod::Propagation);
    EXPECT_EQ(draft.effects.light_resolution, 64);
    EXPECT_TRUE(draft.effects.indirect);
    EXPECT_TRUE(draft.effects.propagation.chroma_subsampling);
    EXPECT_FALSE(draft.effects.ambient_occlusion);
    const Scene preview = withPreset(litScene(), "preview");
    EXPECT_EQ(preview.render.method, RenderMethod::March);
    EXPECT_EQ(preview.render.step, 0.5f);
    EXPECT_EQ(preview.effects.shadows, ShadowMethod::Propagation);
    EXPECT_EQ(preview.effects.light_resolution, 128);
    EXPECT_TRUE(preview.effects.indirect);
    EXPECT_FALSE(preview.effects.propagation.chroma_subsampling);
    // Both read the illumination volume by the B-spline, whatever the scene says.
    nlohmann::json trilinear = litScene();
    trilinear["effects"] = {{"propagation", {{"filter", "trilinear"}}}};
    for (const char* fast : {"draft", "preview"})
        EXPECT_EQ(withPreset(trilinear, fast).effects.propagation.filter, Filter::Tricubic) << fast;
    const Scene final_ = withPreset(litScene(), "final");
    EXPECT_EQ(final_.render.method, RenderMethod::Reference);
    EXPECT_EQ(final_.render.reference.spp, 256);
    // Lights and material are the scene's.
    for (const Scene* s : {&draft, &preview, &final_}) EXPECT_EQ(s->lights.size(), 2u);
}

// The fast presets cut every environment light into 4 lights, whatever K it had; final keeps its K
// (the reference samples the map itself); other lights are untouched.
TEST(QualityPresets, TheFastPresetsCutEnvironmentLightsIntoFour) {
    nlohmann::json scene = litScene();
    scene["lights"].push_back({{"type", "environment"}, {"map", "/shots/sky.exr"}, {"median_cut_lights", 32}});
    scene["lights"].push_back({{"type", "environment"}, {"map", "/shots/dome.exr"}});
    for (const char* fast : {"draft", "preview"}) {
        const Scene s = withPreset(scene, fast);
        ASSERT_EQ(s.lights.size(), 4u);
        EXPECT_FALSE(s.lights[1].environment);
        EXPECT_EQ(s.lights[2].environment->median_cut_lights, 4) << fast;
        EXPECT_EQ(s.lights[3].environment->median_cut_lights, 4) << fast;
    }
    EXPECT_EQ(withPreset(scene, "final").lights[2].environment->median_cut_lights, 32);
}

TEST(QualityPresets, AnEffectTurnedOnKeepsTheScenesSettings) {
    nlohmann::json scene = litScene();
    scene["effects"] = {{"indirect", {{"transport_color", {1.0, 0.6, 0.3}}}},
                        {"ambient_occlusion", {{"shells", 7}}},
                        {"shadows", "propagation"}};
    for (const char* preset : {"draft", "preview"}) {
        const Scene s = withPreset(scene, preset);
        ASSERT_TRUE(s.effects.indirect) << preset;
        EXPECT_EQ(s.effects.indirect->transport_color, glm::vec3(1.0f, 0.6f, 0.3f)) << preset;
        EXPECT_FALSE(s.effects.ambient_occlusion) << preset;   // turned off: measured to add error
    }
}

TEST(QualityPresets, UnknownPresetIsOneLine) {
    nlohmann::json j = litScene();
    try {
        applyQualityPreset(j, "ultra");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "--quality 'ultra': unknown preset (draft, preview, final)");
    }
    const std::string vdb = test::writeBall(test::tempDir("quality_cli"));
    const test::CliResult r = test::runCli("render " + vdb + " --quality ultra --explain");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --quality 'ultra': unknown preset (draft, preview, final)\n");
}

TEST(QualityPresets, OtherOptionsOverrideThePreset) {
    const std::string vdb = test::writeBall(test::tempDir("quality_override"));
    const test::CliResult r = test::runCli("scene " + vdb + " --quality final --spp 8");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Scene s = parseScene(r.out, "scene.json", "");
    EXPECT_EQ(s.render.method, RenderMethod::Reference);
    EXPECT_EQ(s.render.reference.spp, 8);
    const test::CliResult m = test::runCli("scene " + vdb + " --quality final --method march --shadows sat_cone");
    ASSERT_EQ(m.exit_code, 0) << m.err;
    EXPECT_EQ(parseScene(m.out, "scene.json", "").effects.shadows, ShadowMethod::SatCone);
}

}  // namespace
}  // namespace voxlux
