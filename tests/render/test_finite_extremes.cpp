// Numbers stay finite (docs/scene.md, "Extreme values"): every lighting method, on both backends
// and in the Monte Carlo reference, renders every sample finite for legal extremes: lights from
// 1e-30 to 1e38, densities from 1e-8 to the float maximum, Henyey-Greenstein g of +-0.999 and
// +-0.9999999, a surface gradient threshold of 1e-45, emission up to the float maximum on values
// of 1e6 (lighting the medium, with propagation), and point lights on a voxel corner, on the
// volume's face and inside it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>

#include "backend/backend_choice.h"
#include "render/renderer.h"
#include "scene/camera.h"
#include "test_support.h"

namespace voxlux {
namespace {

using test::boxGrid;
using test::volumeFromGrid;

struct Extreme {
    std::string name;
    float density = 0.5f;                   // of every voxel of the 24^3 box
    std::function<void(Scene&)> change;
    bool march_only = false;                // an effect the reference does not render
};

void setPointLight(Scene& s, glm::vec3 position) {
    s.lights[1].position = position;
    s.lights[1].intensity = 1e6f;
}

// The box glowing with its own density at `intensity` (with propagation it also lights itself).
std::function<void(Scene&)> glow(float intensity) {
    return [intensity](Scene& s) {
        EmissionSource e;
        e.grid.name = "density";
        e.intensity = intensity;
        s.volume().emission = {e};
    };
}

std::vector<Extreme> extremes() {
    const auto intensity = [](float i) { return [i](Scene& s) { for (auto& l : s.lights) l.intensity = i; }; };
    const auto g = [](float g) { return [g](Scene& s) { s.volume().material.anisotropy = g; }; };
    return {
        {"lights 1e-30", 0.5f, intensity(1e-30f)},
        {"lights 1e30", 0.5f, intensity(1e30f)},
        {"lights 1e38", 0.5f, intensity(1e38f)},
        {"lights FLT_MAX", 0.5f, intensity(FLT_MAX)},
        {"density 1e-8", 1e-8f, {}},
        {"density 1e6", 1e6f, {}},
        {"density FLT_MAX", FLT_MAX, {}},
        {"g 0.999", 0.5f, g(0.999f)},
        {"g -0.999", 0.5f, g(-0.999f)},
        {"g 0.9999999", 0.5f, g(0.9999999f)},
        {"g -0.9999999", 0.5f, g(-0.9999999f)},
        {"gradient_high 1e-45", 0.5f, [](Scene& s) { s.effects.surface = SurfaceShading{0.0f, 1e-45f}; }, true},
        {"emission 1e38", 0.5f, glow(1e38f)},
        {"emission FLT_MAX, density 1e6", 1e6f, glow(FLT_MAX)},
        {"point light on a voxel corner", 0.5f, [](Scene& s) { setPointLight(s, glm::vec3(12.0f)); }},
        {"point light on the face", 0.5f, [](Scene& s) { setPointLight(s, {0.0f, 11.5f, 11.5f}); }},
        {"point light inside", 0.5f, [](Scene& s) { setPointLight(s, {11.3f, 11.6f, 11.5f}); }},
        {"point light FLT_MAX inside", 0.5f, [](Scene& s) {
             setPointLight(s, {11.3f, 11.6f, 11.5f});
             s.lights[1].intensity = FLT_MAX;
         }},
    };
}

// A directional, a point and an ambient light on a box, with each method's own effects on.
Scene methodScene(ShadowMethod shadows, RenderMethod method) {
    Scene s;
    // The reference tracks up to 65536 null collisions per segment through a dense brick: fewer pixels.
    const bool reference = method == RenderMethod::Reference;
    s.render.width = reference ? 6 : 20;
    s.render.height = reference ? 4 : 14;
    s.render.method = method;
    s.render.reference.spp = 4;
    s.effects.shadows = shadows;
    s.effects.light_resolution = 16;
    if (shadows == ShadowMethod::SatCone) s.effects.ambient_occlusion = AmbientOcclusion{};
    if (shadows == ShadowMethod::Propagation) s.effects.indirect = Indirect{};
    s.volume().material.albedo = glm::vec3(0.9f);
    Light directional = defaultKeyLight();
    Light point;
    point.type = LightType::Point;
    point.position = {30.0f, 28.0f, 20.0f};
    point.intensity = 400.0f;
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.intensity = 0.3f;
    s.lights = {directional, point, ambient};
    Camera camera;
    camera.position = {40.0f, 20.0f, 50.0f};
    camera.look_at = glm::vec3(12.0f);
    s.camera = camera;
    return s;
}

// Counts the samples of `img` (every colour, AOV and alpha) that are not finite.
size_t nonFinite(const RenderImage& img) {
    size_t n = 0;
    for (const auto& px : img.pixels) {
        const float values[] = {px.rgba.x, px.rgba.y, px.rgba.z, px.rgba.w, px.direct.x, px.direct.y, px.direct.z,
                                px.ambient.x, px.ambient.y, px.ambient.z, px.emission.x, px.emission.y,
                                px.emission.z, px.indirect.x, px.indirect.y, px.indirect.z, px.transmittance,
                                px.depth, px.variance};
        for (float v : values) n += !std::isfinite(v);
    }
    return n;
}

struct Method {
    std::string name;
    ShadowMethod shadows;
    RenderMethod method;
};

void expectEveryExtremeFinite(KernelBackend& backend, const std::vector<Method>& methods) {
    for (const Method& m : methods)
        for (const Extreme& e : extremes()) {
            if (e.march_only && m.method == RenderMethod::Reference) continue;
            SCOPED_TRACE(m.name + ", " + e.name + " on " + backend.name());
            Scene scene = methodScene(m.shadows, m.method);
            if (e.change) e.change(scene);
            const auto box = boxGrid({0, 0, 0}, {23, 23, 23}, e.density);
            std::vector<openvdb::FloatGrid::ConstPtr> emission;
            if (!scene.volume().emission.empty()) emission = {box};
            Renderer renderer(scene, volumeFromGrid(box, emission), backend);
            const FrameResult frame = renderer.render(std::nullopt, false);
            EXPECT_EQ(nonFinite(frame.image), 0u);
            // Finite, and not black: the box is lit. Black is right for 1e-30 lights (below float
            // range in the image), and for the reference's 96 paths at density 1e-8 (they rarely
            // collide) and at FLT_MAX (a segment past the collision cap is opaque).
            float peak = 0.0f;
            for (const auto& px : frame.image.pixels) peak = std::max(peak, px.rgba.x);
            const bool black_is_right = e.name == "lights 1e-30" || (m.method == RenderMethod::Reference && e.density != 0.5f);
            if (!black_is_right) {
                EXPECT_GT(peak, 0.0f);
            }
            for (const auto& w : frame.warnings) EXPECT_EQ(w.find("non-finite"), std::string::npos) << w;
        }
}

const std::vector<Method> kMarchMethods = {{"no shadows", ShadowMethod::None, RenderMethod::March},
                                           {"raymarch", ShadowMethod::Raymarch, RenderMethod::March},
                                           {"sat_cone", ShadowMethod::SatCone, RenderMethod::March},
                                           {"propagation", ShadowMethod::Propagation, RenderMethod::March}};

TEST(FiniteExtremes, EveryMethodAndTheReferenceOnCpu) {
    auto cpu = makeCpuBackend();
    std::vector<Method> methods = kMarchMethods;
    methods.push_back({"reference", ShadowMethod::Raymarch, RenderMethod::Reference});
    expectEveryExtremeFinite(*cpu, methods);
}

TEST(FiniteExtremes, EveryMethodOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    expectEveryExtremeFinite(*gl, kMarchMethods);
}

}  // namespace
}  // namespace voxlux
