// Light linking (lights[i].volumes, shadow_volumes; docs/compositing.md): a light linked to one of
// two volumes leaves the other's direct light exactly as with the light off, in every method and
// in the reference (within its noise); a light whose shadow_volumes leave out the volume between
// it and another lights that one as if the first were not there; light groups still sum to the
// beauty; GL agrees with the CPU; bad links are refused by name.
#include <glm/gtx/component_wise.hpp>

#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kLinkSize = 24;

// A ball (radius 2) named `name` at x = `x`.
VolumeSpec ballAt(const std::string& file, const std::string& name, float x) {
    VolumeSpec v;
    v.path = file;
    v.name = name;
    VolumeTransform t;
    t.translate = glm::vec3(x, 0.0f, 0.0f);
    v.transform = t;
    return v;
}

// Balls "left" (x = -4) and "right" (x = 4) seen along -z, both in view and apart in the image
// (left in columns 0-11, right in 12-23), lit by an unlinked key from the camera's side and a
// second light that the tests link.
Scene twoBalls(const std::string& file, ShadowMethod shadows) {
    Scene s;
    s.volumes = {ballAt(file, "left", -4.0f), ballAt(file, "right", 4.0f)};
    s.render.width = s.render.height = kLinkSize;
    s.render.backend = Backend::Cpu;
    s.render.step = 0.5f;
    s.camera = cameraAlong(glm::vec3(0.0f), glm::vec3(0, 0, -1), 20.0f, 40.0f);
    Light key;
    key.direction = glm::normalize(glm::vec3(0.3f, -0.4f, -1.0f));
    key.intensity = 3.0f;
    Light linked;
    linked.type = LightType::Point;
    linked.position = glm::vec3(0.0f, 4.0f, 3.0f);
    linked.color = glm::vec3(1.0f, 0.5f, 0.2f);
    linked.intensity = 60.0f;
    s.lights = {key, linked};
    s.effects.shadows = shadows;
    s.effects.light_resolution = 48;
    if (shadows == ShadowMethod::Propagation) s.effects.indirect = Indirect{};
    s.render.reference.max_bounces = 1;
    return s;
}

// The direct light summed over columns [x0, x1).
glm::dvec3 directIn(const RenderImage& img, int x0, int x1) {
    glm::dvec3 sum(0.0);
    for (int y = 0; y < img.height; ++y)
        for (int x = x0; x < x1; ++x) sum += glm::dvec3(img.pixels[size_t(y) * img.width + x].direct);
    return sum;
}

// The largest difference of the direct light of any pixel in columns [x0, x1).
float largestDirectDifference(const RenderImage& a, const RenderImage& b, int x0, int x1) {
    float largest = 0.0f;
    for (int y = 0; y < a.height; ++y)
        for (int x = x0; x < x1; ++x) {
            const size_t i = size_t(y) * a.width + x;
            largest = std::max(largest, glm::compMax(glm::abs(a.pixels[i].direct - b.pixels[i].direct)));
        }
    return largest;
}

// The standard error of a sum of the reference's pixels over columns [x0, x1), from their
// variances (of the beauty's luminance, which bounds the direct light's with one bounce).
double errorIn(const RenderImage& img, int x0, int x1) {
    double variance = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = x0; x < x1; ++x) variance += img.pixels[size_t(y) * img.width + x].variance;
    return std::sqrt(variance);
}

TEST(LightLinking, ALightLinkedToOneVolumeLeavesTheOthersDirectAsWithTheLightOff) {
    const std::string file = writeBall(tempDir("link-one-of-two"));
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::SatCone, ShadowMethod::Propagation}) {
        SCOPED_TRACE(shadowMethodName(method));
        Scene linked = twoBalls(file, method);
        linked.lights[1].volumes = std::vector<std::string>{"right"};
        Scene off = twoBalls(file, method);
        off.lights[1].enabled = false;
        Scene unlinked = twoBalls(file, method);
        const RenderImage with_link = renderScene(linked), with_light_off = renderScene(off), with_light_on = renderScene(unlinked);
        // The left ball: its direct light is the key's alone, bit for bit.
        EXPECT_EQ(largestDirectDifference(with_link, with_light_off, 0, kLinkSize / 2), 0.0f);
        // The light does reach it when unlinked, and the right ball gets it either way.
        EXPECT_GT(luminance(directIn(with_light_on, 0, kLinkSize / 2)), 1.2 * luminance(directIn(with_light_off, 0, kLinkSize / 2)));
        const double right_linked = luminance(directIn(with_link, kLinkSize / 2, kLinkSize));
        EXPECT_GT(right_linked, 1.2 * luminance(directIn(with_light_off, kLinkSize / 2, kLinkSize)));
        EXPECT_NEAR(right_linked, luminance(directIn(with_light_on, kLinkSize / 2, kLinkSize)), 1e-4 * right_linked);
    }
}

TEST(LightLinking, TheReferenceScattersALinkedLightOnlyInTheVolumesItLights) {
    const std::string file = writeBall(tempDir("link-reference"));
    Scene linked = twoBalls(file, ShadowMethod::Raymarch);
    linked.render.method = RenderMethod::Reference;
    linked.render.reference.spp = 64;
    linked.lights[1].volumes = std::vector<std::string>{"right"};
    Scene off = linked;
    off.lights[1].enabled = false;
    Scene unlinked = linked;
    unlinked.lights[1].volumes.reset();
    const RenderImage a = renderScene(linked), b = renderScene(off), c = renderScene(unlinked);
    const int half = kLinkSize / 2;
    const double left_linked = luminance(directIn(a, 0, half)), left_off = luminance(directIn(b, 0, half));
    EXPECT_NEAR(left_linked, left_off, 4.0 * std::hypot(errorIn(a, 0, half), errorIn(b, 0, half)));
    EXPECT_GT(luminance(directIn(c, 0, half)), 1.2 * left_off);
    const double right_linked = luminance(directIn(a, half, kLinkSize)), right_unlinked = luminance(directIn(c, half, kLinkSize));
    EXPECT_NEAR(right_linked, right_unlinked, 4.0 * std::hypot(errorIn(a, half, kLinkSize), errorIn(c, half, kLinkSize)));
}

// The light travels along -x through the right ball, then the left one.
Scene shadowedBalls(const std::string& file, ShadowMethod shadows) {
    Scene s = twoBalls(file, shadows);
    s.lights[1].type = LightType::Directional;
    s.lights[1].direction = glm::vec3(-1.0f, 0.0f, 0.0f);
    s.lights[1].intensity = 4.0f;
    s.lights.erase(s.lights.begin());   // the key
    return s;
}

TEST(LightLinking, ShadowVolumesLeaveOutTheVolumeBetween) {
    const std::string file = writeBall(tempDir("link-shadows"));
    const int half = kLinkSize / 2;
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::SatCone, ShadowMethod::Propagation}) {
        SCOPED_TRACE(shadowMethodName(method));
        Scene both = shadowedBalls(file, method);
        Scene own = both;
        own.lights[0].shadow_volumes = std::vector<std::string>{"left"};
        // The right ball all but gone, where it was: the light grids keep their box.
        Scene thin = both;
        thin.volumes[1].material.density_scale = 1e-6f;
        const RenderImage shadowed = renderScene(both), unshadowed = renderScene(own), reference = renderScene(thin);
        const double lit = luminance(directIn(unshadowed, 0, half)), thin_lit = luminance(directIn(reference, 0, half));
        EXPECT_GT(lit, 1.5 * luminance(directIn(shadowed, 0, half)));   // the right ball's shadow is gone
        // The same samples through the left ball; the fast methods' grids differ by what the thin
        // ball still holds.
        EXPECT_NEAR(lit, thin_lit, (method == ShadowMethod::Raymarch ? 1e-5 : 1e-3) * thin_lit);
        // The right ball no longer shadows itself either.
        EXPECT_GT(luminance(directIn(unshadowed, half, kLinkSize)), 1.2 * luminance(directIn(shadowed, half, kLinkSize)));
    }
}

TEST(LightLinking, ShadowVolumesInTheReference) {
    const std::string file = writeBall(tempDir("link-shadows-reference"));
    const int half = kLinkSize / 2;
    Scene own = shadowedBalls(file, ShadowMethod::Raymarch);
    own.render.method = RenderMethod::Reference;
    own.render.reference.spp = 64;
    own.lights[0].shadow_volumes = std::vector<std::string>{"left"};
    Scene thin = own;   // unlinked, the right ball all but gone
    thin.lights[0].shadow_volumes.reset();
    thin.volumes[1].material.density_scale = 1e-6f;
    const RenderImage a = renderScene(own), b = renderScene(thin);
    EXPECT_NEAR(luminance(directIn(a, 0, half)), luminance(directIn(b, 0, half)), 4.0 * std::hypot(errorIn(a, 0, half), errorIn(b, 0, half)));
}

TEST(LightLinking, LightGroupsOfLinkedLightsSumToTheBeauty) {
    const std::string file = writeBall(tempDir("link-groups"));
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::SatCone, ShadowMethod::Propagation}) {
        SCOPED_TRACE(shadowMethodName(method));
        Scene s = twoBalls(file, method);
        s.lights[1].volumes = std::vector<std::string>{"right"};
        s.lights[1].group = "warm";
        s.output.aovs = {{"light_groups", std::nullopt}};
        s.effects.indirect.reset();   // a linked light's indirect light reaches every volume (docs/compositing.md)
        const RenderImage img = renderScene(s);
        ASSERT_EQ(img.light_groups.size(), 3u);   // default, warm and emission (black: nothing emits)
        float largest = 0.0f, peak = 0.0f;
        for (size_t i = 0; i < img.pixels.size(); ++i) {
            const glm::vec3 sum = img.light_groups[0].rgb[i] + img.light_groups[1].rgb[i];
            largest = std::max(largest, glm::compMax(glm::abs(sum - glm::vec3(img.pixels[i].rgba))));
            peak = std::max(peak, glm::compMax(glm::vec3(img.pixels[i].rgba)));
        }
        EXPECT_LE(largest, 1e-5f * peak);
        // The warm group's direct light falls on the right ball alone.
        float warm_left = 0.0f;
        for (int y = 0; y < kLinkSize; ++y)
            for (int x = 0; x < kLinkSize / 2; ++x) warm_left = std::max(warm_left, glm::compMax(img.light_groups[1].rgb[size_t(y) * kLinkSize + x]));
        EXPECT_EQ(warm_left, 0.0f);
    }
}

TEST(LightLinking, ALinkedSceneOnGlAgreesWithTheCpuOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    const std::string file = writeBall(tempDir("link-gl"));
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::Propagation}) {
        SCOPED_TRACE(shadowMethodName(method));
        Scene s = twoBalls(file, method);
        s.lights[1].volumes = std::vector<std::string>{"right"};
        s.lights[1].shadow_volumes = std::vector<std::string>{"right"};
        // llvmpipe ends every loop of an invocation past 65535 turns in all (Mesa's
        // LP_MAX_TGSI_LOOP_ITERATIONS): a shadow ray per sample at the default step runs out of
        // them through these balls, so the shadow rays step coarser here.
        s.render.shadow_step = 2.0f;
        const RenderImage cpu = renderScene(s);
        s.render.backend = Backend::Gl;
        const RenderImage on_gl = renderScene(s);
        float largest = 0.0f, peak = 0.0f;
        for (size_t i = 0; i < cpu.pixels.size(); ++i) {
            largest = std::max(largest, glm::compMax(glm::abs(cpu.pixels[i].rgba - on_gl.pixels[i].rgba)));
            peak = std::max(peak, glm::compMax(cpu.pixels[i].rgba));
        }
        EXPECT_LE(largest, 1e-3f * peak);
    }
}

TEST(LightLinking, BadLinksAreRefusedByName) {
    const std::string volumes = R"("volumes": [{"path": "a.vdb", "name": "smoke"}, {"path": "b.vdb", "name": "fire"}])";
    EXPECT_EQ(sceneErrorOf("{" + volumes + R"(, "lights": [{"type": "point", "position": [0, 0, 0], "volumes": ["smok"]}]})"),
              "shot.json: /lights/0/volumes: no volume is named 'smok' (the scene's volumes are 'smoke', 'fire')");
    EXPECT_EQ(sceneErrorOf("{" + volumes + R"(, "lights": [{"shadow_volumes": "smoke"}]})"),
              "shot.json: /lights/0/shadow_volumes: must be a list of volume names");
    EXPECT_EQ(sceneErrorOf("{" + volumes + R"(, "lights": [{"type": "ambient", "volumes": ["smoke"]}]})"),
              "shot.json: /lights/0/volumes: an ambient light lights every volume: link a directional, point or spot light");
}

TEST(LightLinking, TheLinksRoundTripThroughJson) {
    Scene s;
    s.volumes = {ballAt("a.vdb", "smoke", 0.0f), ballAt("b.vdb", "fire", 1.0f)};
    Light l;
    l.volumes = std::vector<std::string>{"fire"};
    l.shadow_volumes = std::vector<std::string>{};
    s.lights = {l};
    const Scene back = sceneFromJson(sceneToJson(s), "shot.json", "/shots");
    EXPECT_EQ(back.lights[0].volumes, l.volumes);
    EXPECT_EQ(back.lights[0].shadow_volumes, l.shadow_volumes);
    const LightLinks links = lightLinks(back);
    ASSERT_EQ(links.sets.size(), 1u);
    EXPECT_EQ(links.sets[0].lit, l.volumes);
}

}  // namespace
}  // namespace voxlux::test
