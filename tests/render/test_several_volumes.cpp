// Several volumes in one scene (shaders/vx_volumes.h): extinction adds where they overlap, so two
// copies at half the density render as one at the whole, in the march (to float rounding) and in
// the reference (within its noise); far-apart volumes render as each alone; a mix of albedos and
// anisotropies, transfer functions and colour grids matches the reference; emission adds, and a
// fire lights the smoke beside it; a moving volume blurs as it does alone; a matte holds out what
// is behind it and a shadow-only volume only shadows; a volume's stages re-run only for its own
// edits; what several volumes do not take yet is refused by name.
#include <filesystem>
#include <functional>
#include <fstream>

#include <glm/gtx/component_wise.hpp>

#include "core/error.h"
#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kSize = 24;

// A volume of the ball file (radius 2 world units at the origin) named `name`, at `density_scale`,
// moved by `translate`.
VolumeSpec ball(const std::string& file, const std::string& name, float density_scale, glm::vec3 translate = glm::vec3(0.0f)) {
    VolumeSpec v;
    v.path = file;
    v.name = name;
    v.material.density_scale = density_scale;
    if (translate != glm::vec3(0.0f)) {
        VolumeTransform t;
        t.translate = translate;
        v.transform = t;
    }
    return v;
}

// `volumes` seen along -z from the camera side of a directional light and an ambient light, with
// ray-marched shadows.
Scene sceneOf(std::vector<VolumeSpec> volumes, glm::vec3 look_at = glm::vec3(0.0f), float fov = 40.0f) {
    Scene s;
    s.volumes = std::move(volumes);
    s.render.width = s.render.height = kSize;
    s.render.backend = Backend::Cpu;
    s.render.step = 0.5f;
    s.camera = cameraAlong(look_at, glm::vec3(0, 0, -1), 12.0f, fov);
    Light key;
    key.direction = glm::normalize(glm::vec3(0.3f, -0.4f, -1.0f));
    key.intensity = 3.0f;
    Light sky;
    sky.type = LightType::Ambient;
    sky.intensity = 0.5f;
    sky.color = glm::vec3(0.6f, 0.8f, 1.0f);
    s.lights = {key, sky};
    return s;
}

// The largest difference of any channel of any pixel, relative to the brightest channel of `a`.
float largestRelativeDifference(const RenderImage& a, const RenderImage& b) {
    float largest = 0.0f, peak = 0.0f;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        largest = std::max(largest, glm::compMax(glm::abs(a.pixels[i].rgba - b.pixels[i].rgba)));
        peak = std::max(peak, glm::compMax(a.pixels[i].rgba));
    }
    EXPECT_GT(peak, 0.1f);   // something is in view
    return largest / peak;
}

// A volume of the fire-ball file tinted by its colour grid and a transfer function that thins its
// edge and turns its core blue.
VolumeSpec tinted(const std::string& file, const std::string& name, glm::vec3 translate = glm::vec3(0.0f)) {
    VolumeSpec v = ball(file, name, 1.0f, translate);
    v.color = GridRef{"Cd", 0};
    v.material.transfer = {{0.0f, 0.0f, glm::vec3(1.0f)}, {0.3f, 0.5f, glm::vec3(1.0f, 0.6f, 0.3f)}, {1.0f, 2.0f, glm::vec3(0.5f, 0.7f, 1.0f)}};
    return v;
}

// A volume of the fire-ball file whose heat glows orange at `intensity`.
VolumeSpec fire(const std::string& file, const std::string& name, float density_scale, float intensity,
                glm::vec3 translate = glm::vec3(0.0f)) {
    VolumeSpec v = ball(file, name, density_scale, translate);
    EmissionSource glow;
    glow.grid = GridRef{"heat", 0};
    glow.color = glm::vec3(1.0f, 0.45f, 0.1f);
    glow.intensity = intensity;
    v.emission = {glow};
    return v;
}

// The sum of the emission AOV over the image.
double emitted(const RenderImage& img) {
    double sum = 0.0;
    for (const auto& p : img.pixels) sum += luminance(p.emission);
    return sum;
}

TEST(SeveralVolumes, TwoCopiesAtHalfTheDensityMarchAsOneAtTheWhole) {
    const std::string file = writeBall(tempDir("several-additive"));
    for (Filter filter : {Filter::Trilinear, Filter::Tricubic}) {
        Scene one = sceneOf({ball(file, "ball", 1.2f)});
        Scene two = sceneOf({ball(file, "a", 0.6f), ball(file, "b", 0.6f)});
        one.render.filter = two.render.filter = filter;
        const RenderImage a = renderScene(one), b = renderScene(two);
        // The same samples, the extinction summed in another order: float rounding only.
        EXPECT_LE(largestRelativeDifference(a, b), 2e-5f) << "filter " << int(filter);
    }
}

TEST(SeveralVolumes, TwoCopiesAtHalfTheDensityTraceAsOneAtTheWholeInTheReference) {
    const std::string file = writeBall(tempDir("several-additive-reference"));
    Scene one = sceneOf({ball(file, "ball", 1.2f)});
    Scene two = sceneOf({ball(file, "a", 0.6f), ball(file, "b", 0.6f)});
    for (Scene* s : {&one, &two}) {
        s->render.width = s->render.height = 12;
        s->render.method = RenderMethod::Reference;
        s->render.reference.spp = 64;
    }
    const auto [mean_one, error_one] = meanLuminanceAndError(renderScene(one));
    const auto [mean_two, error_two] = meanLuminanceAndError(renderScene(two));
    std::printf("  reference, one at s: %.5f +- %.5f; two at s/2: %.5f +- %.5f\n", mean_one, error_one, mean_two, error_two);
    EXPECT_GT(mean_one, 0.02);
    EXPECT_LE(std::abs(mean_one - mean_two), 3.0 * std::hypot(error_one, error_two));
}

// Two volumes far apart, `a` at the left of a wide view and `b` at the right, rendered together
// and each alone. Lit from the camera's side, so neither shadows the other; `adjust` sets the
// scenes' other keys.
struct ApartRenders {
    RenderImage both, a, b;
    // The largest difference of any channel of `both` from the sum of `a` and `b`.
    float largestFromSum() const {
        float largest = 0.0f;
        for (size_t i = 0; i < both.pixels.size(); ++i)
            largest = std::max(largest, glm::compMax(glm::abs(both.pixels[i].rgba - (a.pixels[i].rgba + b.pixels[i].rgba))));
        return largest;
    }
};

ApartRenders renderApart(VolumeSpec a, VolumeSpec b, const std::function<void(Scene&)>& adjust = [](Scene&) {}) {
    a.transform = VolumeTransform{};
    a.transform->translate = glm::vec3(-3.0f, 0.0f, 0.0f);
    b.transform = VolumeTransform{};
    b.transform->translate = glm::vec3(3.0f, 0.5f, -1.0f);
    const auto scene = [&](std::vector<VolumeSpec> v) {
        Scene s = sceneOf(std::move(v), glm::vec3(0.0f), 60.0f);
        s.lights[0].direction = glm::vec3(0, 0, -1);
        adjust(s);
        return s;
    };
    return {renderScene(scene({a, b})), renderScene(scene({a})), renderScene(scene({b}))};
}

TEST(SeveralVolumes, FarApartTheyRenderAsEachAlone) {
    const std::string file = writeBall(tempDir("several-apart"));
    const ApartRenders r = renderApart(ball(file, "left", 1.0f), ball(file, "right", 0.5f));
    int covered_left = 0, covered_right = 0;
    for (size_t i = 0; i < r.both.pixels.size(); ++i) {
        covered_left += r.a.pixels[i].rgba.w > 0.1f;
        covered_right += r.b.pixels[i].rgba.w > 0.1f;
    }
    EXPECT_GT(covered_left, 20);
    EXPECT_GT(covered_right, 20);
    EXPECT_LE(r.largestFromSum(), 1e-5f);
}

// A volume of several emits as it does alone: beside a ball that emits nothing, far from it, its
// pixels are its own single-volume march's, emission AOV and all.
TEST(SeveralVolumes, AnEmittingVolumeMarchesAsItDoesAlone) {
    const std::string dir = tempDir("several-emitting-apart");
    const std::string fire_file = writeFireBall(dir), ball_file = writeBall(dir);
    for (Filter filter : {Filter::Trilinear, Filter::Tricubic}) {
        const ApartRenders r = renderApart(fire(fire_file, "fire", 1.0f, 4.0f), ball(ball_file, "smoke", 0.5f),
                                           [&](Scene& s) { s.render.filter = filter; });
        float largest = r.largestFromSum(), peak = 0.0f;
        for (size_t i = 0; i < r.both.pixels.size(); ++i) {
            largest = std::max(largest, glm::compMax(glm::abs(r.both.pixels[i].emission - r.a.pixels[i].emission)));
            peak = std::max(peak, glm::compMax(r.a.pixels[i].emission));
        }
        std::printf("  filter %d: brightest emission %.4f, largest difference %.3g\n", int(filter), peak, largest);
        EXPECT_GT(peak, 0.5f);
        EXPECT_LE(largest, 2e-5f * peak) << "filter " << int(filter);
    }
}

// Emission adds where volumes overlap: two copies at half the density and half the glow march as
// one at the whole, to float rounding.
TEST(SeveralVolumes, TwoEmittingCopiesAtHalfMarchAsOneAtTheWhole) {
    const std::string file = writeFireBall(tempDir("several-emitting-additive"));
    for (Filter filter : {Filter::Trilinear, Filter::Tricubic}) {
        Scene one = sceneOf({fire(file, "fire", 1.2f, 3.0f)});
        Scene two = sceneOf({fire(file, "a", 0.6f, 1.5f), fire(file, "b", 0.6f, 1.5f)});
        one.render.filter = two.render.filter = filter;
        const RenderImage a = renderScene(one), b = renderScene(two);
        EXPECT_GT(emitted(a), 1.0);
        EXPECT_LE(largestRelativeDifference(a, b), 2e-5f) << "filter " << int(filter);
        EXPECT_NEAR(emitted(a), emitted(b), 2e-5 * emitted(a));
    }
}

// The same in the reference, with no light but the glow: within its noise, the emitted light
// scattered included. Without scattering (albedo 0) the march's emission is the reference's.
TEST(SeveralVolumes, TwoEmittingCopiesAtHalfTraceAsOneAtTheWholeInTheReference) {
    const std::string file = writeFireBall(tempDir("several-emitting-reference"));
    const auto reference = [](std::vector<VolumeSpec> v, RenderMethod method) {
        Scene s = sceneOf(std::move(v));
        s.lights.clear();
        s.render.width = s.render.height = 12;
        s.render.method = method;
        s.render.step = 0.1f;
        s.render.reference.spp = 64;
        return s;
    };
    const auto [mean_one, error_one] = meanLuminanceAndError(renderScene(reference({fire(file, "fire", 1.2f, 3.0f)}, RenderMethod::Reference)));
    const auto [mean_two, error_two] =
        meanLuminanceAndError(renderScene(reference({fire(file, "a", 0.6f, 1.5f), fire(file, "b", 0.6f, 1.5f)}, RenderMethod::Reference)));
    std::printf("  reference, one glowing at s: %.5f +- %.5f; two at s/2: %.5f +- %.5f\n", mean_one, error_one, mean_two, error_two);
    EXPECT_GT(mean_one, 0.05);
    EXPECT_LE(std::abs(mean_one - mean_two), 3.0 * std::hypot(error_one, error_two));

    std::vector<VolumeSpec> dark{fire(file, "a", 0.6f, 1.5f), fire(file, "b", 0.6f, 1.5f)};
    for (VolumeSpec& v : dark) v.material.albedo = glm::vec3(0.0f);
    const auto [mean_march, unused] = meanLuminanceAndError(renderScene(reference(dark, RenderMethod::March)));
    const auto [mean_traced, error] = meanLuminanceAndError(renderScene(reference(dark, RenderMethod::Reference)));
    std::printf("  albedo 0: march %.5f, reference %.5f +- %.5f\n", mean_march, mean_traced, error);
    EXPECT_GT(mean_traced, 0.05);
    EXPECT_LE(std::abs(mean_march - mean_traced), 3.0 * error + 0.01 * mean_traced);
}

// A matte or a shadow-only volume that has emission shows none of it: alone it renders nothing.
TEST(SeveralVolumes, AMatteOrShadowOnlyVolumeEmitsNothing) {
    const std::string file = writeFireBall(tempDir("several-emitting-roles"));
    for (VolumeRole role : {VolumeRole::Matte, VolumeRole::ShadowOnly})
        for (RenderMethod method : {RenderMethod::March, RenderMethod::Reference}) {
            VolumeSpec held = fire(file, "fire", 1.0f, 4.0f);
            held.role = role;
            Scene s = sceneOf({held});
            s.render.method = method;
            s.render.reference.spp = 4;
            float largest = 0.0f;
            for (const auto& p : renderScene(s).pixels) largest = std::max({largest, glm::compMax(p.rgba), glm::compMax(p.emission)});
            EXPECT_EQ(largest, 0.0f) << kVolumeRoleNames[size_t(role)] << ", method " << int(method);
        }
}

// Propagation carries a fire's glow into the smoke beside it, scattered with the smoke's own
// albedo: with no light in the scene the smoke is lit, in proportion to the glow.
TEST(SeveralVolumes, AFireLightsTheSmokeBesideItThroughPropagation) {
    const std::string dir = tempDir("several-emitting-propagation");
    const std::string fire_file = writeFireBall(dir), ball_file = writeBall(dir);
    const auto smokeLight = [&](float glow, glm::vec3 smoke_albedo) {
        VolumeSpec smoke = ball(ball_file, "smoke", 1.0f, glm::vec3(2.5f, 0.0f, 0.0f));
        smoke.material.albedo = smoke_albedo;
        Scene s = sceneOf({fire(fire_file, "fire", 1.0f, glow, glm::vec3(-2.5f, 0.0f, 0.0f)), smoke}, glm::vec3(0.0f), 70.0f);
        s.lights.clear();
        s.effects.shadows = ShadowMethod::Propagation;
        Indirect in;
        in.model = IndirectModel::Kniss;
        in.transport_color = glm::vec3(0.6f);
        s.effects.indirect = in;
        const RenderImage img = renderScene(s);
        double sum = 0.0;   // the smoke's half of the image, beyond the fire's reach
        for (int y = 0; y < kSize; ++y)
            for (int x = kSize * 3 / 5; x < kSize; ++x) sum += luminance(img.pixels[size_t(y * kSize + x)].indirect);
        return sum;
    };
    const double lit = smokeLight(4.0f, glm::vec3(0.9f)), brighter = smokeLight(8.0f, glm::vec3(0.9f));
    const double black = smokeLight(4.0f, glm::vec3(0.0f));
    std::printf("  the smoke's indirect light: %.5f under a glow of 4, %.5f under 8, %.5f at albedo 0\n", lit, brighter, black);
    EXPECT_GT(lit, 1e-3);
    EXPECT_NEAR(brighter, 2.0 * lit, 1e-4 * lit);
    EXPECT_EQ(black, 0.0);
}

// A volume of several takes its transfer function and colour grid as it does alone: beside a
// plain ball, far from it, its pixels are its own single-volume march's.
TEST(SeveralVolumes, ATransferFunctionAndAColourGridMarchAsTheyDoAlone) {
    const std::string dir = tempDir("several-tinted-apart");
    const std::string fire_file = writeFireBall(dir), ball_file = writeBall(dir);
    for (Filter filter : {Filter::Trilinear, Filter::Tricubic}) {
        const ApartRenders r = renderApart(tinted(fire_file, "tinted"), ball(ball_file, "plain", 0.5f), [&](Scene& s) { s.render.filter = filter; });
        float peak = 0.0f;
        glm::vec3 tinted_sum(0.0f);
        for (const auto& p : r.a.pixels) {
            peak = std::max(peak, glm::compMax(p.rgba));
            tinted_sum += glm::vec3(p.rgba);
        }
        const float largest = r.largestFromSum();
        std::printf("  filter %d: the tinted volume's colour sum (%.3f, %.3f, %.3f), largest difference %.3g\n", int(filter), tinted_sum.x,
                    tinted_sum.y, tinted_sum.z, largest);
        EXPECT_GT(peak, 0.2f);
        EXPECT_GT(tinted_sum.x, 1.2f * tinted_sum.z);   // its tints show: redder than its bluish light
        EXPECT_LE(largest, 2e-5f * peak) << "filter " << int(filter);
    }
}

// Under motion blur (1 frame a second: the fire ball moves half a unit either way over the
// shutter) a moving volume of several blurs as it does alone, glow and all, beside a still ball
// that blurs not at all. Under ambient light only: the light is the same wherever the medium moved.
TEST(SeveralVolumes, AMovingVolumeBlursAsItDoesAlone) {
    const std::string dir = tempDir("several-moving-apart");
    const std::string fire_file = writeFireBall(dir), ball_file = writeBall(dir);
    for (Filter filter : {Filter::Trilinear, Filter::Tricubic}) {
        const auto ambientOnly = [&](bool blurred) {
            return [=](Scene& s) {
                s.lights = {s.lights[1]};
                s.render.filter = filter;
                if (!blurred) return;
                MotionBlur blur;
                blur.fps = 1.0f;
                blur.samples = 4;
                s.render.motion_blur = blur;
            };
        };
        const ApartRenders r = renderApart(fire(fire_file, "fire", 1.0f, 4.0f), ball(ball_file, "smoke", 0.5f), ambientOnly(true));
        const RenderImage still = renderApart(fire(fire_file, "fire", 1.0f, 4.0f), ball(ball_file, "smoke", 0.5f), ambientOnly(false)).both;
        float peak = 0.0f, blurred = 0.0f;
        for (size_t i = 0; i < r.both.pixels.size(); ++i) {
            peak = std::max(peak, glm::compMax(r.a.pixels[i].rgba + r.b.pixels[i].rgba));
            blurred = std::max(blurred, std::abs(r.both.pixels[i].rgba.w - still.pixels[i].rgba.w));
        }
        const float largest = r.largestFromSum();
        std::printf("  filter %d: largest difference %.3g of %.3f; the blur moves alpha by %.3f\n", int(filter), largest, peak, blurred);
        EXPECT_GT(blurred, 0.05f);   // it does blur
        EXPECT_LE(largest, 2e-5f * peak) << "filter " << int(filter);
    }
}

// The reference blurs several volumes as the march does: each path at its time sees each volume
// where it moved (a glowing ball behind a still smoke, both of albedo 0: the march is exact but
// for its steps).
TEST(SeveralVolumes, TheReferenceBlursAMovingVolumeAsTheMarchDoes) {
    const std::string dir = tempDir("several-moving-reference");
    VolumeSpec glow = fire(writeFireBall(dir), "fire", 1.0f, 3.0f, glm::vec3(-0.8f, 0.0f, 0.0f));
    VolumeSpec smoke = ball(writeBall(dir), "smoke", 0.6f, glm::vec3(1.5f, 0.0f, 1.0f));
    glow.material.albedo = smoke.material.albedo = glm::vec3(0.0f);
    Scene march = sceneOf({glow, smoke});
    march.lights.clear();
    march.render.width = march.render.height = 12;
    march.render.step = 0.1f;
    MotionBlur blur;
    blur.fps = 1.0f;
    blur.samples = 8;
    march.render.motion_blur = blur;
    Scene reference = march;
    reference.render.method = RenderMethod::Reference;
    reference.render.reference.spp = 64;
    const auto [mean_march, unused] = meanLuminanceAndError(renderScene(march));
    const auto [mean_reference, error] = meanLuminanceAndError(renderScene(reference));
    std::printf("  blurred glow: march %.5f, reference %.5f +- %.5f\n", mean_march, mean_reference, error);
    EXPECT_GT(mean_reference, 0.05);
    EXPECT_LE(std::abs(mean_march - mean_reference), 3.0 * error + 0.01 * mean_reference);
}

// The march's single scattering (fine steps) matches the reference's first bounce, in the mean.
void expectSingleScatteringAsTheReference(Scene march) {
    march.lights.pop_back();   // the directional light alone: single scattering is all the march adds
    march.render.width = march.render.height = 12;
    march.render.step = 0.1f;
    march.render.shadow_step = 0.1f;
    Scene reference = march;
    reference.render.method = RenderMethod::Reference;
    reference.render.reference.spp = 256;
    reference.render.reference.max_bounces = 1;
    const auto [mean_march, unused] = meanLuminanceAndError(renderScene(march));
    const auto [mean_reference, error] = meanLuminanceAndError(renderScene(reference));
    std::printf("  single scattering: march %.5f, reference %.5f +- %.5f\n", mean_march, mean_reference, error);
    EXPECT_GT(mean_reference, 0.005);
    EXPECT_LE(std::abs(mean_march - mean_reference), 3.0 * error + 0.01 * mean_reference);
}

// Where a tinted volume (a transfer function and a colour grid) overlaps a plain one, the mix is
// the reference's: its extinction bound (the table's largest) and its tints are the march's.
TEST(SeveralVolumes, ATintedVolumeMixesAsTheReferenceDoes) {
    const std::string dir = tempDir("several-tinted-mix");
    VolumeSpec plain = ball(writeBall(dir), "plain", 0.8f, glm::vec3(0.8f, 0.3f, 0.5f));
    plain.material.anisotropy = 0.5f;
    expectSingleScatteringAsTheReference(sceneOf({tinted(writeFireBall(dir), "tinted", glm::vec3(-0.8f, 0.0f, 0.0f)), plain}));
}

// Where a white forward-scattering volume overlaps a blue isotropic one, the march's single
// scattering (fine steps) matches the reference's first bounce: the mix of albedo and g is the same.
TEST(SeveralVolumes, OverlappingMaterialsMixAsTheReferenceDoes) {
    const std::string file = writeBall(tempDir("several-mix"));
    VolumeSpec white = ball(file, "white", 0.8f, glm::vec3(-0.8f, 0.0f, 0.0f));
    white.material.albedo = glm::vec3(0.95f);
    white.material.anisotropy = 0.7f;
    VolumeSpec blue = ball(file, "blue", 0.8f, glm::vec3(0.8f, 0.3f, 0.5f));
    blue.material.albedo = glm::vec3(0.2f, 0.4f, 0.9f);
    blue.material.anisotropy = -0.2f;
    expectSingleScatteringAsTheReference(sceneOf({white, blue}));
}

TEST(SeveralVolumes, AnEditOfOneVolumeReloadsNoOther) {
    const std::string file = writeBall(tempDir("several-edit"));
    Scene scene = sceneOf({ball(file, "a", 0.6f), ball(file, "b", 0.6f, glm::vec3(1.0f, 0, 0)), ball(file, "c", 0.6f, glm::vec3(-1.0f, 0, 0))});
    Renderer renderer(scene);
    renderer.render(std::nullopt, false);
    scene.volumes[2].material.density_scale = 0.3f;
    renderer.setScene(scene);
    const FrameResult edited = renderer.render(std::nullopt, false);
    EXPECT_NE(std::find(edited.reused.begin(), edited.reused.end(), "volumes: b"), edited.reused.end());
    EXPECT_EQ(std::find(edited.reused.begin(), edited.reused.end(), "volumes: c"), edited.reused.end());
}

// The gizmo's drag: a move of one volume re-runs the framing, light and march stages, no load or
// brick of any volume.
TEST(SeveralVolumes, AMoveOfOneVolumeReloadsAndRebricksNone) {
    const std::string file = writeBall(tempDir("several-move"));
    Scene scene = sceneOf({ball(file, "a", 0.6f), ball(file, "b", 0.6f, glm::vec3(1.0f, 0, 0))});
    Renderer renderer(scene);
    const RenderImage before = renderer.render(std::nullopt, false).image;
    scene.volumes[1].transform->translate.y += 0.5f;
    renderer.setScene(scene);
    const FrameResult moved = renderer.render(std::nullopt, false);
    for (const char* kept : {"load", "brick", "classify", "volumes"})
        EXPECT_NE(std::find(moved.reused.begin(), moved.reused.end(), kept), moved.reused.end()) << kept;
    EXPECT_EQ(std::find(moved.reused.begin(), moved.reused.end(), "march"), moved.reused.end());
    EXPECT_GT(largestRelativeDifference(before, moved.image), 0.05f);   // it moved
}

// A disabled volume (the viewer's visibility toggle) renders as if it were not in the scene, and
// turning it off and on reloads no other volume.
TEST(SeveralVolumes, ADisabledVolumeRendersAsIfItWereNotThereAndReloadsNoOther) {
    const std::string file = writeBall(tempDir("several-disabled"));
    Scene scene = sceneOf({ball(file, "a", 0.6f), ball(file, "hidden", 2.0f, glm::vec3(0.5f, 0, 0)), ball(file, "c", 0.4f, glm::vec3(-1.0f, 0, 0))});
    Renderer renderer(scene);
    renderer.render(std::nullopt, false);
    const auto reusedOnToggle = [&](bool on) {
        scene.volumes[1].enabled = on;
        renderer.setScene(scene);
        const FrameResult r = renderer.render(std::nullopt, false);
        return std::make_pair(r.image, std::find(r.reused.begin(), r.reused.end(), "volumes: c") != r.reused.end());
    };
    const auto [without_hidden, c_kept_off] = reusedOnToggle(false);
    EXPECT_TRUE(c_kept_off);
    EXPECT_TRUE(reusedOnToggle(true).second);
    EXPECT_EQ(largestRelativeDifference(without_hidden, renderScene(sceneOf({ball(file, "a", 0.6f), ball(file, "c", 0.4f, glm::vec3(-1.0f, 0, 0))}))), 0.0f);
}

// An instance is its volume placed again, reading the same bricks: a volume with two instances
// renders as two volumes of the same file at those poses, to the bit, and 100 instances take the
// atlas of one.
TEST(SeveralVolumes, InstancesRenderAsCopiesAndShareTheBricks) {
    const std::string file = writeBall(tempDir("several-instances"));
    VolumeTransform left, right;
    left.translate = glm::vec3(-2.5f, 0.0f, 0.0f);
    right.translate = glm::vec3(2.0f, 0.5f, -1.0f);
    right.rotate = glm::vec3(30.0f, 0.0f, 45.0f);
    right.scale = glm::vec3(0.75f);
    VolumeSpec instanced = ball(file, "ball", 1.0f);
    instanced.instances = {left, right};
    VolumeSpec a = ball(file, "a", 1.0f), b = ball(file, "b", 1.0f);
    a.transform = left;
    b.transform = right;
    const RenderImage copies = renderScene(sceneOf({a, b}, glm::vec3(0.0f), 60.0f));
    const RenderImage instances = renderScene(sceneOf({instanced}, glm::vec3(0.0f), 60.0f));
    float largest = 0.0f, covered = 0.0f;
    for (size_t i = 0; i < copies.pixels.size(); ++i) {
        largest = std::max(largest, glm::compMax(glm::abs(copies.pixels[i].rgba - instances.pixels[i].rgba)));
        covered = std::max(covered, copies.pixels[i].rgba.w);
    }
    EXPECT_GT(covered, 0.5f);
    EXPECT_EQ(largest, 0.0f);

    const size_t one = Renderer(sceneOf({ball(file, "ball", 1.0f)})).render(std::nullopt, false).atlas_bytes;
    VolumeSpec hundred = ball(file, "ball", 1.0f);
    for (int i = 0; i < 100; ++i) {
        VolumeTransform t;
        t.translate = glm::vec3(float(i % 10) * 5.0f, float(i / 10) * 5.0f, 0.0f);
        hundred.instances.push_back(t);
    }
    Scene crowd = sceneOf({hundred});
    crowd.render.width = crowd.render.height = 8;
    const size_t many = Renderer(crowd).render(std::nullopt, false).atlas_bytes;
    std::printf("  atlas: one volume %zu bytes, 100 instances %zu bytes\n", one, many);
    EXPECT_LE(double(many), 1.1 * double(one));
}

TEST(SeveralVolumes, InstancesAreReadAndWrittenBack) {
    const Scene s = parseScene(R"({"volumes": [{"path": "smoke.vdb", "instances": [{"translate": [1, 2, 3]}, {"rotate": [0, 90, 0], "scale": 2}]}]})",
                               "shot.json", "");
    ASSERT_EQ(s.volume().instances.size(), 2u);
    EXPECT_EQ(s.volume().instances[0].translate, glm::vec3(1, 2, 3));
    EXPECT_EQ(placedVolumeCount(s), 2u);
    const Scene back = sceneFromJson(sceneToJson(s), "back.json", "");
    ASSERT_EQ(back.volume().instances.size(), 2u);
    EXPECT_EQ(back.volume().instances[1].scale, glm::vec3(2.0f));
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "instances": [{"keys": []}]}]})"),
              "shot.json: /volumes/0/instances/0/keys: an instance is still: translate, rotate and scale, or a matrix");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "instances": []}]})"),
              "shot.json: /volumes/0/instances: expected a list of transforms ({\"translate\", \"rotate\", \"scale\"} or {\"matrix\"})");
}

TEST(SeveralVolumes, WhatSeveralVolumesDoNotTakeYetIsRefusedByName) {
    const std::string two = R"("volumes": [{"path": "a.vdb"}, {"path": "b.vdb", "material": {"transfer_function_2d": "ct_tissue"}}])";
    EXPECT_EQ(sceneErrorOf("{" + two + "}"),
              "shot.json: /volumes/1/material/transfer_function_2d: set: a volume of several takes a 1D transfer function "
              "(transfer_function) only, so far");
    const std::string three = R"({"grid": "t"}, {"grid": "t"}, {"grid": "t"})";
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "emission": [)" + three + R"(]}, {"path": "b.vdb", "emission": [)" + three + "]}]}"),
              "shot.json: /volumes/1/emission: brings the scene's emission sources to 6: the volumes take at most 4 together");
    EXPECT_NO_THROW(parseScene(R"({"volumes": [{"path": "a.vdb", "emission": [)" + three + R"(]}, {"path": "b.vdb", "enabled": false, "emission": [)" +
                                   three + "]}]}",
                               "shot.json", ""));
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb"}, {"path": "b.vdb"}], "effects": {"perturbation": {}}})"),
              "shot.json: /effects/perturbation: set with 2 volumes: several volumes render without it, so far");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb"}, {"path": "b.vdb", "material": {"anisotropy": 0.5}}], "effects": {"indirect": {}}})"),
              "shot.json: /effects/indirect: the diffusion model takes its profile from one material, and volume 'b' has another albedo "
              "or anisotropy than 'a': give them one, or take the kniss model (transport_color)");
    EXPECT_NO_THROW(parseScene(R"({"volumes": [{"path": "a.vdb"}, {"path": "b.vdb", "material": {"anisotropy": 0.5}}],
        "effects": {"indirect": {"transport_color": [0.6, 0.5, 0.4]}}})", "shot.json", ""));
}

// Every method's light grid holds every volume: a volume between the light and another shadows
// it, in the march's shadow rays, the SAT's cones and the propagation's sweeps alike.
TEST(SeveralVolumes, AVolumeShadowsAnotherInEveryMethod) {
    const std::string file = writeBall(tempDir("several-shadow"));
    const auto scene = [&](std::vector<VolumeSpec> v, ShadowMethod shadows) {
        Scene s = sceneOf(std::move(v), glm::vec3(2.0f, 0.0f, 0.0f), 60.0f);
        s.lights = {s.lights[0]};
        s.lights[0].direction = glm::vec3(-1.0f, 0.0f, 0.0f);   // from +x: through the blocker onto the lit one
        s.effects.shadows = shadows;
        return s;
    };
    // The lit volume's half of the image (x < 2 in the world: the left columns).
    const auto leftLuminance = [](const RenderImage& img) {
        double sum = 0.0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize / 2; ++x) sum += luminance(glm::vec3(img.pixels[size_t(y * kSize + x)].rgba));
        return sum;
    };
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::SatCone, ShadowMethod::Propagation}) {
        const double alone = leftLuminance(renderScene(scene({ball(file, "lit", 1.0f)}, method)));
        const double shadowed = leftLuminance(renderScene(scene({ball(file, "lit", 1.0f), ball(file, "blocker", 1.0f, glm::vec3(4.0f, 0, 0))}, method)));
        std::printf("  %s: the lit volume's light %.3f alone, %.3f behind the blocker\n", shadowMethodName(method).c_str(), alone, shadowed);
        EXPECT_GT(alone, 1.0);
        EXPECT_LT(shadowed, 0.5 * alone) << shadowMethodName(method);
    }
}

// A frame where the first volume has nothing visible (a smoke not yet emitted) renders the others
// lit, in every method, as when the empty one comes second; only a frame where no volume has
// anything visible is refused.
TEST(SeveralVolumes, AnEmptyFirstVolumeLeavesTheOthersLit) {
    const std::string file = writeBall(tempDir("several-empty-first"));
    const VolumeSpec empty = ball(file, "empty", 0.0f), lit = ball(file, "lit", 0.8f, glm::vec3(0.5f, 0, 0));
    for (ShadowMethod method : {ShadowMethod::Raymarch, ShadowMethod::SatCone, ShadowMethod::Propagation}) {
        const auto scene = [&](std::vector<VolumeSpec> v) {
            Scene s = sceneOf(std::move(v));
            s.effects.shadows = method;
            return s;
        };
        EXPECT_LE(largestRelativeDifference(renderScene(scene({lit, empty})), renderScene(scene({empty, lit}))), 1e-5f) << shadowMethodName(method);
    }
    VolumeSpec also_empty = ball(file, "also_empty", 0.0f, glm::vec3(1.0f, 0, 0));
    try {
        renderScene(sceneOf({empty, also_empty}));
        ADD_FAILURE() << "rendered a frame with nothing visible";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(", nor in the other volume"), std::string::npos) << e.what();
    }
}

// The light grid methods see two copies at half the density as one at the whole: the same medium
// on a grid resampled from the volumes (shaders/vx_volumes.h) rather than box-filtered from one.
// So do propagation's indirect light, by either model, and its eye pass.
TEST(SeveralVolumes, TheLightGridMethodsSeeTwoHalvesAsTheWhole) {
    const std::string file = writeBall(tempDir("several-grid-additive"));
    Indirect kniss;
    kniss.model = IndirectModel::Kniss;
    kniss.transport_color = glm::vec3(0.7f, 0.5f, 0.3f);
    struct Case {
        const char* name;
        ShadowMethod shadows;
        std::optional<Indirect> indirect;
        bool eye_pass = false;
    };
    for (const Case& c : {Case{"sat_cone", ShadowMethod::SatCone, std::nullopt}, Case{"propagation", ShadowMethod::Propagation, std::nullopt},
                          Case{"propagation+indirect", ShadowMethod::Propagation, Indirect{}},
                          Case{"propagation+kniss+eye_pass", ShadowMethod::Propagation, kniss, true}}) {
        Scene one = sceneOf({ball(file, "ball", 1.2f)});
        Scene two = sceneOf({ball(file, "a", 0.6f), ball(file, "b", 0.6f)});
        for (Scene* s : {&one, &two}) {
            s->effects.shadows = c.shadows;
            s->effects.ambient_occlusion = AmbientOcclusion{};
            s->effects.indirect = c.indirect;
            s->effects.propagation.eye_pass = c.eye_pass;
        }
        const FrameResult a_result = Renderer(one).render(std::nullopt, false), b_result = Renderer(two).render(std::nullopt, false);
        const RenderImage &a = a_result.image, &b = b_result.image;
        double difference = 0.0, total = 0.0, indirect = 0.0;
        for (size_t i = 0; i < a.pixels.size(); ++i) {
            difference += std::abs(luminance(glm::vec3(a.pixels[i].rgba)) - luminance(glm::vec3(b.pixels[i].rgba)));
            total += luminance(glm::vec3(a.pixels[i].rgba));
            indirect += luminance(b.pixels[i].indirect);
        }
        std::printf("  %s: mean relative difference %.4f, indirect %.3f of %.3f\n", c.name, difference / total, indirect, total);
        EXPECT_GT(total, 1.0);
        EXPECT_EQ(indirect > 0.01 * total, c.indirect.has_value()) << c.name;
        EXPECT_LE(difference / total, 0.03) << c.name;
    }
}

// A slab of uniform extinction in front of the ball (between it and the camera), beside the light's
// way to the ball, which comes from above.
VolumeSpec slabInFront(const std::string& dir, VolumeRole role) {
    VolumeSpec v;
    v.path = dir + "/slab.vdb";
    openvdb::io::File(v.path).write({boxGrid({-40, -40, 40}, {39, 39, 49}, 1.0f, 0.1)});   // z 4 to 5 world units
    v.name = "slab";
    v.material.density_scale = 0.4f;
    v.role = role;
    return v;
}

// A matte cuts what is behind it by its transmittance and adds no colour and no alpha of its own:
// the compositor's holdout.
TEST(SeveralVolumes, AMatteCutsTheVolumeBehindItByItsTransmittance) {
    const std::string dir = tempDir("several-matte");
    const std::string file = writeBall(dir);
    const auto lit = [](std::vector<VolumeSpec> v) {
        Scene s = sceneOf(std::move(v));
        s.lights = {s.lights[0]};
        s.lights[0].direction = glm::vec3(0.0f, -1.0f, 0.0f);   // from above: the slab does not shadow the ball
        return s;
    };
    const RenderImage ball_alone = renderScene(lit({ball(file, "ball", 1.0f)}));
    const RenderImage slab_seen = renderScene(lit({slabInFront(dir, VolumeRole::Visible)}));
    const RenderImage held_out = renderScene(lit({ball(file, "ball", 1.0f), slabInFront(dir, VolumeRole::Matte)}));
    const RenderImage matte_alone = renderScene(lit({slabInFront(dir, VolumeRole::Matte)}));
    float largest = 0.0f, peak = 0.0f, matte_largest = 0.0f, slab_opacity = 0.0f;
    for (size_t i = 0; i < held_out.pixels.size(); ++i) {
        const float T = slab_seen.pixels[i].transmittance;
        slab_opacity = std::max(slab_opacity, 1.0f - T);
        largest = std::max(largest, glm::compMax(glm::abs(held_out.pixels[i].rgba - ball_alone.pixels[i].rgba * T)));
        peak = std::max(peak, glm::compMax(ball_alone.pixels[i].rgba));
        matte_largest = std::max(matte_largest, glm::compMax(glm::abs(matte_alone.pixels[i].rgba)));
    }
    EXPECT_GT(slab_opacity, 0.25f);   // e^(-0.4) over its 1-unit depth
    EXPECT_LE(largest, 1e-4f * peak);
    EXPECT_EQ(matte_largest, 0.0f);
}

// A shadow-only volume darkens the volume it shadows and is not seen: where only it lies on the
// camera's rays, the image is empty.
TEST(SeveralVolumes, AShadowOnlyVolumeShadowsAndIsNotSeen) {
    const std::string file = writeBall(tempDir("several-shadow-only"));
    const auto scene = [&](std::vector<VolumeSpec> v) {
        Scene s = sceneOf(std::move(v), glm::vec3(2.0f, 0.0f, 0.0f), 60.0f);
        s.lights = {s.lights[0]};
        s.lights[0].direction = glm::vec3(-1.0f, 0.0f, 0.0f);
        return s;
    };
    VolumeSpec blocker = ball(file, "blocker", 1.0f, glm::vec3(4.0f, 0, 0));
    const RenderImage alone = renderScene(scene({ball(file, "lit", 1.0f)}));
    const RenderImage blocker_seen = renderScene(scene({blocker}));
    blocker.role = VolumeRole::ShadowOnly;
    const RenderImage shadowed = renderScene(scene({ball(file, "lit", 1.0f), blocker}));
    double lit_alone = 0.0, lit_shadowed = 0.0;
    float unseen = 0.0f;
    int blocker_pixels = 0;
    for (size_t i = 0; i < alone.pixels.size(); ++i) {
        if (alone.pixels[i].rgba.w > 0.0f) {
            lit_alone += luminance(glm::vec3(alone.pixels[i].rgba));
            lit_shadowed += luminance(glm::vec3(shadowed.pixels[i].rgba));
        } else if (blocker_seen.pixels[i].rgba.w > 0.1f) {
            ++blocker_pixels;
            unseen = std::max(unseen, glm::compMax(glm::abs(shadowed.pixels[i].rgba)));
        }
    }
    EXPECT_GT(blocker_pixels, 20);
    EXPECT_EQ(unseen, 0.0f);
    EXPECT_LT(lit_shadowed, 0.5 * lit_alone);
    // Where the lit volume is seen, its alpha is its own: the blocker adds none.
    for (size_t i = 0; i < alone.pixels.size(); ++i) EXPECT_NEAR(shadowed.pixels[i].rgba.w, alone.pixels[i].rgba.w, 1e-5f);
}

// The reference holds a matte out as the march does: its alpha is the visible volume's coverage,
// and a matte alone traces to nothing.
TEST(SeveralVolumes, TheReferenceHoldsOutAMatteAsTheMarchDoes) {
    const std::string dir = tempDir("several-matte-reference");
    const std::string file = writeBall(dir);
    Scene march = sceneOf({ball(file, "ball", 1.0f), slabInFront(dir, VolumeRole::Matte)});
    march.lights = {march.lights[0]};
    march.lights[0].direction = glm::vec3(0.0f, -1.0f, 0.0f);
    march.render.width = march.render.height = 12;
    march.render.step = march.render.shadow_step = 0.1f;
    Scene reference = march;
    reference.render.method = RenderMethod::Reference;
    reference.render.reference.spp = 256;
    reference.render.reference.max_bounces = 1;
    const RenderImage a = renderScene(march), b = renderScene(reference);
    double alpha_march = 0.0, alpha_reference = 0.0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        alpha_march += a.pixels[i].rgba.w;
        alpha_reference += b.pixels[i].rgba.w;
    }
    const auto [mean_march, unused] = meanLuminanceAndError(a);
    const auto [mean_reference, error] = meanLuminanceAndError(b);
    std::printf("  held out: march %.5f, reference %.5f +- %.5f; alpha sums %.3f, %.3f\n", mean_march, mean_reference, error, alpha_march,
                alpha_reference);
    EXPECT_GT(mean_reference, 0.002);
    EXPECT_LE(std::abs(mean_march - mean_reference), 3.0 * error + 0.01 * mean_reference);
    EXPECT_NEAR(alpha_reference, alpha_march, 0.02 * alpha_march);
    Scene matte_only = reference;
    matte_only.volumes = {slabInFront(dir, VolumeRole::Matte)};
    for (const auto& p : renderScene(matte_only).pixels) EXPECT_EQ(p.rgba, glm::vec4(0.0f));
}

// output.aovs "coverage": a channel per volume, named by it, which sum to the alpha; a matte's is 0;
// one visible volume's is the alpha.
TEST(SeveralVolumes, EachVolumesCoverageSumsToTheAlpha) {
    const std::string dir = tempDir("several-coverage");
    const std::string file = writeBall(dir);
    const std::string scene = dir + "/coverage.json";
    std::ofstream(scene) << R"({"volumes": [
        {"name": "smoke", "path": ")" << file << R"("},
        {"name": "dust", "path": ")" << file << R"(", "transform": {"translate": [1.5, 0.5, 1]}, "material": {"density_scale": 0.5}},
        {"name": "holdout", "path": ")" << file << R"(", "transform": {"translate": [-1, -1, 3], "scale": 0.5}, "role": "matte"}],
      "camera": {"position": [0, 0, 12], "look_at": [0, 0, 0], "fov": 40},
      "render": {"resolution": [32, 32]},
      "output": {"path": ")" << dir << R"(/coverage.exr", "pixel_type": "float", "aovs": ["coverage"]}})";
    const CliResult r = runCli("render " + scene);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Exr exr = readExr(dir + "/coverage.exr");
    ASSERT_TRUE(exr.planes.count("coverage.smoke") && exr.planes.count("coverage.dust") && exr.planes.count("coverage.holdout"));
    float largest = 0.0f, matte = 0.0f, smoke = 0.0f, dust = 0.0f;
    for (size_t i = 0; i < exr.planes.at("A").size(); ++i) {
        const float sum = exr.planes.at("coverage.smoke")[i] + exr.planes.at("coverage.dust")[i] + exr.planes.at("coverage.holdout")[i];
        largest = std::max(largest, std::abs(sum - exr.planes.at("A")[i]));
        matte = std::max(matte, exr.planes.at("coverage.holdout")[i]);
        smoke = std::max(smoke, exr.planes.at("coverage.smoke")[i]);
        dust = std::max(dust, exr.planes.at("coverage.dust")[i]);
    }
    EXPECT_GT(smoke, 0.5f);
    EXPECT_GT(dust, 0.2f);
    EXPECT_EQ(matte, 0.0f);
    EXPECT_LE(largest, 1e-5f);

    const CliResult one = runCli("render " + file + " --res 16x16 --set 'output.aovs=[\"coverage\"]' --pixel-type float -o " + dir + "/one.exr");
    ASSERT_EQ(one.exit_code, 0) << one.err;
    const Exr single = readExr(dir + "/one.exr");
    ASSERT_TRUE(single.planes.count("coverage.ball"));
    EXPECT_EQ(single.planes.at("coverage.ball"), single.planes.at("A"));
}

// Under motion blur each volume's coverage is the mean over the pixel's rays, as the alpha is.
TEST(SeveralVolumes, UnderMotionBlurEachVolumesCoverageStillSumsToTheAlpha) {
    const std::string dir = tempDir("several-coverage-blurred");
    const std::string fire_file = writeFireBall(dir), ball_file = writeBall(dir);
    const std::string scene = dir + "/coverage.json";
    std::ofstream(scene) << R"({"volumes": [
        {"name": "fire", "path": ")" << fire_file << R"("},
        {"name": "smoke", "path": ")" << ball_file << R"(", "transform": {"translate": [1.5, 0.5, 1]}}],
      "camera": {"position": [0, 0, 12], "look_at": [0, 0, 0], "fov": 40},
      "render": {"resolution": [32, 32], "motion_blur": {"fps": 1, "samples": 4}},
      "output": {"path": ")" << dir << R"(/coverage.exr", "pixel_type": "float", "aovs": ["coverage"]}})";
    const CliResult r = runCli("render " + scene);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Exr exr = readExr(dir + "/coverage.exr");
    float largest = 0.0f, fire = 0.0f;
    for (size_t i = 0; i < exr.planes.at("A").size(); ++i) {
        largest = std::max(largest, std::abs(exr.planes.at("coverage.fire")[i] + exr.planes.at("coverage.smoke")[i] - exr.planes.at("A")[i]));
        fire = std::max(fire, exr.planes.at("coverage.fire")[i]);
    }
    EXPECT_GT(fire, 0.3f);
    EXPECT_LE(largest, 1e-5f);
}

// A volume after the first whose file is missing or damaged is named, and nothing is written.
TEST(SeveralVolumes, ABadSecondFileIsNamedAndNothingIsWritten) {
    const std::string dir = tempDir("several-bad-file");
    const std::string file = writeBall(dir);
    std::ofstream(dir + "/truncated.vdb") << "OpenVDB";
    for (const std::string& second : {dir + "/missing.vdb", dir + "/truncated.vdb"}) {
        std::ofstream(dir + "/bad.json") << R"({"volumes": [{"name": "a", "path": ")" << file << R"("}, {"name": "b", "path": ")" << second
                                         << R"("}], "render": {"resolution": [16, 16]}, "output": {"path": ")" << dir << R"(/bad.exr"}})";
        const CliResult r = runCli("render " + dir + "/bad.json");
        EXPECT_EQ(r.exit_code, 2);
        EXPECT_EQ(linesStartingWith(r.err, "voxlux: error: ").rfind("voxlux: error: " + second + ": ", 0), 0u) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir + "/bad.exr"));
    }
}

TEST(SeveralVolumes, RolesAreReadAndWrittenBack) {
    const Scene s = parseScene(R"({"volumes": [{"path": "a.vdb"}, {"path": "b.vdb", "role": "matte"}, {"path": "c.vdb", "role": "shadow_only"}]})",
                               "shot.json", "");
    EXPECT_EQ(s.volumes[0].role, VolumeRole::Visible);
    EXPECT_EQ(s.volumes[1].role, VolumeRole::Matte);
    EXPECT_EQ(s.volumes[2].role, VolumeRole::ShadowOnly);
    EXPECT_EQ(sceneFromJson(sceneToJson(s), "back.json", "").volumes[2].role, VolumeRole::ShadowOnly);
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "role": "holdout"}]})"),
              "shot.json: /volumes/0/role: 'holdout' is not one of visible, matte, shadow_only");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb", "role": "matte"}, "output": {"path": "a.exr", "deep": true}})"),
              "shot.json: /output: deep output with a volume of role matte or shadow_only: its deep samples would carry every "
              "volume's opacity, so far");
}

TEST(SeveralVolumes, TheGlBackendMarchesThemAsTheCpuDoes) {
    VOXLUX_REQUIRE_GL(gl);
    const std::string dir = tempDir("several-gl");
    const std::string file = writeBall(dir);
    VolumeSpec matte = ball(file, "matte", 0.5f, glm::vec3(0.0f, -1.5f, 3.0f));
    matte.role = VolumeRole::Matte;
    Scene cpu = sceneOf({tinted(writeFireBall(dir), "a", glm::vec3(-0.8f, 0, 0)), ball(file, "b", 0.5f, glm::vec3(0.8f, 0.3f, 0.5f)), matte});
    cpu.volumes[1].material.albedo = glm::vec3(0.2f, 0.4f, 0.9f);
    EmissionSource glow;   // the second volume's: its sources sit past the first's bricks
    glow.grid = GridRef{"density", 0};
    glow.color = glm::vec3(1.0f, 0.5f, 0.2f);
    cpu.volumes[1].emission = {glow};
    Scene on_gl = cpu;
    on_gl.render.backend = Backend::Gl;
    EXPECT_LE(largestRelativeDifference(renderScene(cpu), renderScene(on_gl)), 1e-3f);
    MotionBlur blur;   // the tinted volume moves (its file's velocity), the others stand still
    blur.fps = 1.0f;
    blur.samples = 2;
    cpu.render.motion_blur = on_gl.render.motion_blur = blur;
    EXPECT_LE(largestRelativeDifference(renderScene(cpu), renderScene(on_gl)), 1e-3f) << "under motion blur";
}

}  // namespace
}  // namespace voxlux::test
