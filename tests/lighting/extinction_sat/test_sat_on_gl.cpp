// Extinction-SAT lighting on the GL backend against the CPU (gl_agreement.h): the SATs are the
// same integers, every cached optical depth agrees to float rounding, and the rendered AOVs match.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lighting/extinction_sat/kernel/light_cache.h"
#include "backend/backend_choice.h"
#include "backend/gl/gl_agreement.h"
#include "lighting/extinction_sat/extinction_sat_stages.h"
#include "render/renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

using namespace gl_agreement;

// Ambient light with colour-bleeding AO, and SAT-cone shadows from a directional light, a point
// light inside the volume and a spot light, on a coarse light grid.
Scene satScene() {
    Scene s = baseScene();
    s.effects.shadows = ShadowMethod::SatCone;
    s.effects.ambient_occlusion = AmbientOcclusion{5, 0.6f};
    s.effects.color_bleeding = 0.7f;
    s.effects.light_resolution = 40;
    s.effects.cone = {3.0f, 24, 0.1f};
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.color = glm::vec3(0.5f, 0.6f, 0.8f);
    ambient.intensity = 0.4f;
    s.lights = {directionalLight(), pointLight(), spotLight(), ambient};
    s.volume().emission = {EmissionSource{}};   // white, for makeVolume(true)
    return s;
}

// The light caches themselves: the SATs are the same integers and every cached optical depth
// agrees to float rounding (CPU rows and GL cells sum the same terms in the same order; only
// multiply-add fusion may differ).
TEST(GlBackend, LightCacheMatchesCpu) {
    VOXLUX_REQUIRE_GL(gl);
    const Scene scene = satScene();
    const LoadedVolume volume = makeVolume(true);
    auto cpu = makeCpuBackend();
    Renderer on_cpu(scene, volume, *cpu), on_gl(scene, volume, *gl);
    on_cpu.prepare(std::nullopt, false);
    on_gl.prepare(std::nullopt, false);
    auto satOf = [](const Renderer& r) { return dynamic_cast<const SatStage&>(r.graph().stage("sat")).sat().words; };
    EXPECT_TRUE(satOf(on_cpu) == satOf(on_gl)) << "CPU and GL SATs differ";
    const LightCache &c = *on_cpu.lightingOutput<LightCache>(), &g = *on_gl.lightingOutput<LightCache>();
    ASSERT_EQ(c.channels, 3 + 3);  // RGB ambient occlusion, three lights
    ASSERT_EQ(c.values.size(), g.values.size());
    for (int ch = 0; ch < c.channels; ++ch) {
        double peak = 0.0, worst = 0.0;
        for (size_t i = ch; i < c.values.size(); i += size_t(c.channels)) {
            peak = std::max(peak, double(std::abs(c.values[i])));
            worst = std::max(worst, double(std::abs(c.values[i] - g.values[i])));
        }
        EXPECT_GT(peak, 0.0) << "channel " << ch << " is empty";
        EXPECT_LE(worst, 1e-5 * peak) << "channel " << ch;
        std::printf("  light-cache channel %d: peak tau %.3g, max |gl - cpu| / peak %.2g\n", ch, peak,
                    peak > 0 ? worst / peak : 0.0);
    }
}

TEST(GlBackend, MatchesCpuWithSatLighting) {
    VOXLUX_REQUIRE_GL(gl);
    const auto stats = expectMatch(renderBoth(makeVolume(true), satScene(), *gl));
    EXPECT_GT(stats[kDirect].peak, 0.0);
    EXPECT_GT(stats[kAmbient].peak, 0.0);
}

}  // namespace
}  // namespace voxlux::test
