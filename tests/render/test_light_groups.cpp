// Light groups (output.aovs "light_groups", src/render/light_group_passes.h): the layers sum to
// the beauty in every method and in the reference; a group's layer is the render with its lights
// alone, emission's the render with no light; the EXR carries lightgroup.<name>.R/G/B and lists
// them; bad group names and deep output with groups are refused by name.
#include <filesystem>
#include <fstream>

#include <ImfStringVectorAttribute.h>
#include <glm/gtx/component_wise.hpp>

#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kGroupsSize = 24;

// The ball (or fire-ball) file seen along -z, lit by a key (group "key"), a point fill and an
// ambient sky (group "fill") and a rim light that names no group (the default group).
Scene groupedScene(const std::string& file, ShadowMethod shadows) {
    Scene s;
    s.volumes[0].path = file;
    s.volumes[0].name = "ball";
    s.render.width = s.render.height = kGroupsSize;
    s.render.backend = Backend::Cpu;
    s.render.step = 0.5f;
    s.camera = cameraAlong(glm::vec3(0.0f), glm::vec3(0, 0, -1), 12.0f, 40.0f);
    Light key;
    key.group = "key";
    key.direction = glm::normalize(glm::vec3(0.3f, -0.4f, -1.0f));
    key.intensity = 3.0f;
    Light fill;
    fill.group = "fill";
    fill.type = LightType::Point;
    fill.position = glm::vec3(-3.0f, 1.0f, 2.0f);
    fill.color = glm::vec3(0.5f, 0.7f, 1.0f);
    fill.intensity = 20.0f;
    Light rim;
    rim.direction = glm::normalize(glm::vec3(-0.5f, 0.2f, 1.0f));
    rim.intensity = 2.0f;
    Light sky;
    sky.group = "fill";
    sky.type = LightType::Ambient;
    sky.intensity = 0.3f;
    s.lights = {key, fill, rim, sky};
    s.effects.shadows = shadows;
    s.effects.light_resolution = 32;
    if (shadows == ShadowMethod::SatCone) s.effects.ambient_occlusion = AmbientOcclusion{};
    if (shadows == ShadowMethod::Propagation) s.effects.indirect = Indirect{};
    s.output.aovs = {{"light_groups", std::nullopt}};
    return s;
}

// The fire ball's heat glowing orange.
void addGlow(Scene& s) {
    EmissionSource glow;
    glow.grid = GridRef{"heat", 0};
    glow.color = glm::vec3(1.0f, 0.45f, 0.1f);
    glow.intensity = 2.0f;
    s.volumes[0].emission = {glow};
}

std::vector<std::string> layerNames(const RenderImage& img) {
    std::vector<std::string> names;
    for (const LightGroupLayer& l : img.light_groups) names.push_back(l.name);
    return names;
}

const LightGroupLayer& layer(const RenderImage& img, const std::string& name) {
    for (const LightGroupLayer& l : img.light_groups)
        if (l.name == name) return l;
    throw std::logic_error("no layer " + name);
}

float peakOf(const RenderImage& img) {
    float peak = 0.0f;
    for (const auto& p : img.pixels) peak = std::max(peak, glm::compMax(glm::vec3(p.rgba)));
    return peak;
}

// The largest difference between the layers' sum and the beauty's colour, relative to its peak.
float sumToBeauty(const RenderImage& img) {
    float largest = 0.0f;
    for (size_t i = 0; i < img.pixels.size(); ++i) {
        glm::vec3 sum(0.0f);
        for (const LightGroupLayer& l : img.light_groups) sum += l.rgb[i];
        largest = std::max(largest, glm::compMax(glm::abs(sum - glm::vec3(img.pixels[i].rgba))));
    }
    return largest / peakOf(img);
}

// The largest difference between `layer` and the beauty of `alone`, relative to `alone`'s peak or
// `scale`, whichever is larger.
float layerAgainst(const LightGroupLayer& l, const RenderImage& alone, float scale) {
    float largest = 0.0f;
    for (size_t i = 0; i < alone.pixels.size(); ++i) largest = std::max(largest, glm::compMax(glm::abs(l.rgb[i] - glm::vec3(alone.pixels[i].rgba))));
    return largest / std::max(peakOf(alone), scale);
}

// The scene with only the lights of `group` ("" the default group) on, or with `group`
// "emission" only its emission, and no light groups. The emission is turned down, not taken
// away: its grid keeps the bricks and the light grid as they were.
Scene onlyGroup(Scene s, const std::string& group) {
    for (Light& l : s.lights) l.enabled = l.group == group;
    if (group != "emission")
        for (EmissionSource& e : s.volumes[0].emission) e.intensity = 0.0f;
    s.output.aovs.clear();
    return s;
}

TEST(LightGroups, TheScenesGroupsAreItsLightsGroupsThenDefault) {
    Scene s = groupedScene("ball.vdb", ShadowMethod::Raymarch);
    const LightGroups groups = lightGroups(s);
    EXPECT_EQ(groups.names, (std::vector<std::string>{"key", "fill", "default"}));
    EXPECT_EQ(groups.of_light, (std::vector<int>{0, 1, 2, 1}));
    EXPECT_EQ(lightGroupMarches(s), 3);
    addGlow(s);
    EXPECT_EQ(lightGroupMarches(s), 4);   // the emitted light's march
    s.lights.clear();
    EXPECT_EQ(lightGroups(s).names, std::vector<std::string>{"default"});
    s.output.aovs.clear();
    EXPECT_TRUE(lightGroups(s).names.empty());
    EXPECT_EQ(lightGroupMarches(s), 1);
}

// Every method: the layers sum to the beauty, each group's layer is the render of its lights
// alone (the default group's too), and the beauty is the render without light groups: the
// medium's isotropic phase makes propagation's shared illumination volume exact per group.
TEST(LightGroups, LayersSumToTheBeautyAndAreEachGroupAloneInEveryMethod) {
    const std::string file = writeBall(tempDir("light-groups-methods"));
    for (ShadowMethod method : {ShadowMethod::None, ShadowMethod::Raymarch, ShadowMethod::SatCone, ShadowMethod::Propagation}) {
        SCOPED_TRACE(shadowMethodName(method));
        const Scene scene = groupedScene(file, method);
        const RenderImage grouped = renderScene(scene);
        EXPECT_EQ(layerNames(grouped), (std::vector<std::string>{"key", "fill", "default", "emission"}));
        EXPECT_LE(sumToBeauty(grouped), 1e-5f);
        const float peak = peakOf(grouped);
        EXPECT_GT(peak, 0.1f);
        for (const auto& [name, group] : {std::pair<std::string, std::string>{"key", "key"}, {"fill", "fill"}, {"default", ""}}) {
            SCOPED_TRACE(name);
            EXPECT_LE(layerAgainst(layer(grouped, name), renderScene(onlyGroup(scene, group)), peak), 1e-5f);
            EXPECT_GT(glm::compMax(layer(grouped, name).rgb[size_t(kGroupsSize / 2 * kGroupsSize + kGroupsSize / 2)]), 1e-3f);
        }
        for (const glm::vec3& c : layer(grouped, "emission").rgb) EXPECT_EQ(c, glm::vec3(0.0f));
        Scene ungrouped = scene;
        ungrouped.output.aovs.clear();
        const RenderImage beauty = renderScene(ungrouped);
        EXPECT_TRUE(beauty.light_groups.empty());
        float largest = 0.0f;
        for (size_t i = 0; i < beauty.pixels.size(); ++i)
            largest = std::max(largest, glm::compMax(glm::abs(beauty.pixels[i].rgba - grouped.pixels[i].rgba)));
        EXPECT_LE(largest / peak, 1e-5f);
    }
}

// Under propagation the illumination volume holds its lights' light together and each light keeps
// its phase, scaled by the fraction of their light that arrives: exact for one light or an
// isotropic phase. With light groups each group has its own volume, so a group's layer is its
// lights alone even under a strongly forward phase, and the beauty (their sum) moves towards the
// per-light answer by a measured amount.
TEST(LightGroups, UnderPropagationEachGroupKeepsItsOwnShadowAtAnyPhase) {
    Scene scene = groupedScene(writeBall(tempDir("light-groups-phase")), ShadowMethod::Propagation);
    scene.volumes[0].material.anisotropy = 0.6f;
    const RenderImage grouped = renderScene(scene);
    const float peak = peakOf(grouped);
    EXPECT_LE(sumToBeauty(grouped), 1e-5f);
    EXPECT_LE(layerAgainst(layer(grouped, "key"), renderScene(onlyGroup(scene, "key")), peak), 1e-5f);
    Scene ungrouped = scene;
    ungrouped.output.aovs.clear();
    const RenderImage shared = renderScene(ungrouped);
    float largest = 0.0f;
    for (size_t i = 0; i < shared.pixels.size(); ++i)
        largest = std::max(largest, glm::compMax(glm::abs(shared.pixels[i].rgba - grouped.pixels[i].rgba)));
    std::printf("  g = 0.6: the beauty with light groups differs from the one without by %.4f of its peak\n", double(largest / peak));
    EXPECT_GT(largest / peak, 1e-4f);   // the groups' own volumes are not the shared one's
    EXPECT_LE(largest / peak, 0.2f);
}

// Emission is its own group: its layer is the render with every light off (under propagation with
// indirect light, the emitted light that the medium scatters included), and the rest still sum.
TEST(LightGroups, EmissionIsItsOwnGroup) {
    const std::string file = writeFireBall(tempDir("light-groups-emission"));
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::Propagation}) {
        SCOPED_TRACE(shadowMethodName(method));
        Scene scene = groupedScene(file, method);
        addGlow(scene);
        const RenderImage grouped = renderScene(scene);
        EXPECT_LE(sumToBeauty(grouped), 1e-5f);
        const RenderImage glow = renderScene(onlyGroup(scene, "emission"));
        EXPECT_GT(peakOf(glow), 0.1f);
        EXPECT_LE(layerAgainst(layer(grouped, "emission"), glow, peakOf(grouped)), 1e-5f);
        EXPECT_LE(layerAgainst(layer(grouped, "key"), renderScene(onlyGroup(scene, "key")), peakOf(grouped)), 1e-5f);
    }
}

// The reference splits each path's contributions by the group of the light they came from (and
// ambient light by the ambient lights' groups), on the same samples: the layers sum to the beauty.
TEST(LightGroups, ReferenceLayersSumToTheBeautyAtEqualSamples) {
    Scene scene = groupedScene(writeFireBall(tempDir("light-groups-reference")), ShadowMethod::Raymarch);
    addGlow(scene);
    scene.render.method = RenderMethod::Reference;
    scene.render.reference.spp = 4;
    scene.render.reference.max_bounces = 4;
    const RenderImage grouped = renderScene(scene);
    EXPECT_EQ(layerNames(grouped), (std::vector<std::string>{"key", "fill", "default", "emission"}));
    EXPECT_LE(sumToBeauty(grouped), 1e-5f);
    for (const LightGroupLayer& l : grouped.light_groups) EXPECT_GT(glm::compMax(l.rgb[size_t(kGroupsSize / 2 * kGroupsSize + kGroupsSize / 2)]), 1e-3f) << l.name;
}

TEST(LightGroups, GlLayersSumAndAgreeWithTheCpusOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    const std::string file = writeFireBall(tempDir("light-groups-gl"));
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::Propagation}) {
        SCOPED_TRACE(shadowMethodName(method));
        Scene scene = groupedScene(file, method);
        addGlow(scene);
        const RenderImage cpu = renderScene(scene);
        scene.render.backend = Backend::Gl;
        const RenderImage on_gl = renderScene(scene);
        EXPECT_LE(sumToBeauty(on_gl), 1e-5f);
        ASSERT_EQ(layerNames(on_gl), layerNames(cpu));
        float largest = 0.0f;
        for (size_t l = 0; l < cpu.light_groups.size(); ++l)
            for (size_t i = 0; i < cpu.pixels.size(); ++i)
                largest = std::max(largest, glm::compMax(glm::abs(cpu.light_groups[l].rgb[i] - on_gl.light_groups[l].rgb[i])));
        EXPECT_LE(largest / peakOf(cpu), 1e-3f);
    }
}

// The EXR has a layer lightgroup.<name> per group, listed in voxlux/lightGroups, which sum to RGB.
TEST(LightGroups, TheExrCarriesAndListsTheLayers) {
    const std::string dir = tempDir("light-groups-exr");
    const std::string ball = writeBall(dir);
    const std::string scene = dir + "/groups.json";
    std::ofstream(scene) << R"({"volume": {"path": ")" << ball << R"("},
      "lights": [{"type": "directional", "direction": [0, -1, -1], "intensity": 3, "group": "key"},
                 {"type": "point", "position": [-3, 1, 2], "intensity": 20, "group": "fill"},
                 {"type": "ambient", "intensity": 0.2}],
      "camera": {"position": [0, 0, 12], "look_at": [0, 0, 0], "fov": 40},
      "render": {"resolution": [16, 16], "backend": "cpu"},
      "output": {"path": ")" << dir << R"(/groups.exr", "pixel_type": "float", "aovs": ["light_groups"]}})";
    const CliResult r = runCli("render " + scene);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Exr exr = readExr(dir + "/groups.exr");
    const std::vector<std::string> listed{"lightgroup.key", "lightgroup.fill", "lightgroup.default", "lightgroup.emission"};
    EXPECT_EQ(exr.header.typedAttribute<Imf::StringVectorAttribute>("voxlux/lightGroups").value(), listed);
    float largest = 0.0f, peak = 0.0f;
    for (const char* c : {"R", "G", "B"}) {
        for (size_t i = 0; i < exr.planes.at(c).size(); ++i) {
            float sum = 0.0f;
            for (const std::string& name : listed) sum += exr.planes.at(name + "." + c)[i];
            largest = std::max(largest, std::abs(sum - exr.planes.at(c)[i]));
            peak = std::max(peak, exr.planes.at(c)[i]);
        }
    }
    EXPECT_GT(peak, 0.1f);
    EXPECT_LE(largest, 1e-5f * peak);
}

TEST(LightGroups, BadGroupsAreRefusedByName) {
    const std::string v = R"({"volume": {"path": "a.vdb"}, )";
    EXPECT_EQ(sceneErrorOf(v + R"("lights": [{"type": "ambient", "group": "key.fill"}]})"),
              "shot.json: /lights/0/group: 'key.fill' is not a layer name: use letters, digits, '_' and '-'");
    EXPECT_EQ(sceneErrorOf(v + R"("lights": [{"type": "directional", "group": ""}]})"),
              "shot.json: /lights/0/group: '' is not a layer name: use letters, digits, '_' and '-'");
    EXPECT_EQ(sceneErrorOf(v + R"("lights": [{"type": "point", "position": [0, 0, 0], "group": "emission"}]})"),
              "shot.json: /lights/0/group: 'emission' is the emitted light's own group (lightgroup.emission)");
    EXPECT_EQ(sceneErrorOf(v + R"("output": {"deep": true, "aovs": ["light_groups"]}})"),
              "shot.json: /output: deep output with the light_groups AOV: the deep samples carry the beauty alone, so far; write the "
              "groups in a render of their own");
}

}  // namespace
}  // namespace voxlux::test
