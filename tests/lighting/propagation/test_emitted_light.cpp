// Emission lighting the medium in the fast path (src/lighting/propagation/emitted_light.h): a
// glowing core inside a scattering shell, against the Monte Carlo reference.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <openvdb/openvdb.h>

#include "render/renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// A ball of radius 20 voxels (voxel 0.1): a core of radius 6 voxels, extinction `core` per world
// unit, holding a "flame" grid of 1, in a shell of extinction `shell`. Written to a file, as the
// renderer reads one.
std::string writeGlowingCore(const std::string& dir, float shell, float core) {
    auto density = openvdb::FloatGrid::create(0.0f);
    auto flame = openvdb::FloatGrid::create(0.0f);
    for (auto g : {density, flame}) {
        g->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
        g->setGridClass(openvdb::GRID_FOG_VOLUME);
    }
    density->setName("density");
    flame->setName("flame");
    auto d = density->getAccessor();
    auto f = flame->getAccessor();
    for (int z = -20; z <= 20; ++z)
        for (int y = -20; y <= 20; ++y)
            for (int x = -20; x <= 20; ++x) {
                const float r = std::sqrt(float(x * x + y * y + z * z));
                if (r > 20.0f) continue;
                d.setValue({x, y, z}, r <= 6.0f ? core : shell);
                if (r <= 6.0f) f.setValue({x, y, z}, 1.0f);
            }
    const std::string path = dir + "/core.vdb";
    openvdb::io::File(path).write({density, flame});
    return path;
}

Scene glowingCoreScene(const std::string& path) {
    Scene s;
    s.volume().path = path;
    s.render.width = 48;
    s.render.height = 48;
    s.render.backend = Backend::Cpu;
    s.render.step = 0.25f;
    s.volume().material.albedo = glm::vec3(0.8f);
    EmissionSource glow;
    glow.grid = GridRef{"flame", 0};
    glow.color = glm::vec3(1.0f, 0.5f, 0.2f);
    glow.intensity = 4.0f;
    s.volume().emission = {glow};
    s.camera = cameraAlong(glm::vec3(0.0f), {0.3f, -1.0f, -0.2f}, 8.0f, 36.0f);
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.indirect = Indirect{};
    return s;
}

// Mean luminance of the scattered light (indirect AOV) and of the emission seen directly.
struct Glow {
    double scattered = 0.0, emitted = 0.0;
};
Glow glowOf(const RenderImage& img) {
    Glow g;
    for (const auto& p : img.pixels) {
        g.scattered += luminance(p.indirect);
        g.emitted += luminance(p.emission);
    }
    g.scattered /= double(img.pixels.size());
    g.emitted /= double(img.pixels.size());
    return g;
}

// The glow a core adds to its shell (the indirect AOV: emission scattered once or more) against
// the reference's, on the CPU, where the shell is optically thin (radius 2 optical depths): around
// a dense core within 20%; around a thin core the fast glow is 1.20x the converged reference's
// (4096 spp), so within 25% is asked there. In a thick shell (radius 8) the fast path's series of
// scattering orders ends too soon (docs/accuracy.md): it stays under the reference, by at most 5x.
TEST(EmittedLight, AGlowingCoreLightsItsShellAsTheReferenceDoes) {
    struct Case {
        float shell, core, low, high;   // the fast glow over the reference's, allowed
    };
    for (const Case c : {Case{1.0f, 1.0f, 0.8f, 1.25f}, Case{1.0f, 10.0f, 0.8f, 1.2f}, Case{4.0f, 4.0f, 0.2f, 1.0f}}) {
        const std::string name = "emitted_light_" + std::to_string(int(c.shell)) + "_" + std::to_string(int(c.core));
        Scene s = glowingCoreScene(writeGlowingCore(tempDir(name), c.shell, c.core));
        const Glow fast = glowOf(Renderer(s).render(std::nullopt, false).image);
        s.render.method = RenderMethod::Reference;
        s.render.reference.spp = 1024;  // its noise is under 1% of the thin shell's glow
        const Glow truth = glowOf(Renderer(s).render(std::nullopt, false).image);
        std::printf("shell %.0f, core %.0f: scattered glow %.5f, reference %.5f (x %.2f); emission seen %.5f vs %.5f\n",
                    double(c.shell), double(c.core), fast.scattered, truth.scattered, fast.scattered / truth.scattered,
                    fast.emitted, truth.emitted);
        EXPECT_GE(fast.scattered, c.low * truth.scattered) << name;
        EXPECT_LE(fast.scattered, c.high * truth.scattered) << name;
    }
}

// A light edit updates the lights selectively and leaves the emitted light in the volume: the
// result equals an entire update of the edited scene, and the glow is there with no light at all.
TEST(EmittedLight, ALightEditKeepsItAndMatchesAnEntireUpdate) {
    Scene s = glowingCoreScene(writeGlowingCore(tempDir("emitted_light_edit"), 1.0f, 4.0f));
    Light key;
    key.direction = glm::normalize(glm::vec3(-0.4f, 0.3f, -1.0f));
    key.intensity = 2.0f;
    s.lights = {key};
    Renderer edited(s);
    edited.prepare(std::nullopt, false);
    s.lights[0].intensity = 3.0f;
    s.lights[0].color = glm::vec3(1.0f, 0.7f, 0.5f);
    edited.setScene(s);
    const FrameResult r = edited.prepare(std::nullopt, false);
    ASSERT_TRUE(r.light_update);
    EXPECT_EQ(r.light_update->mode, LightUpdate::Mode::Selective) << r.light_update->reason;
    Renderer entire(s);
    entire.prepare(std::nullopt, false);
    const std::vector<float>& a = edited.lightingOutput<IlluminationVolume>()->values;
    const std::vector<float>& b = entire.lightingOutput<IlluminationVolume>()->values;
    ASSERT_EQ(a.size(), b.size());
    double peak = 0.0, error = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        peak = std::max(peak, double(std::abs(b[i])));
        error = std::max(error, double(std::abs(a[i] - b[i])));
    }
    std::printf("selective against entire: max difference %.3g of the peak %.3g\n", error / peak, peak);
    EXPECT_LE(error, 1e-5 * peak);

    s.lights.clear();
    Renderer unlit(s);
    unlit.prepare(std::nullopt, false);
    const IlluminationVolume& glow = *unlit.lightingOutput<IlluminationVolume>();
    const float indirect_peak = *std::max_element(glow.values.begin() + long(glow.indirectOffset()), glow.values.end());
    EXPECT_GT(indirect_peak, 0.0f);
}

// Emitted light is swept through the extinction alone, also when a 2D transfer function's
// regions give the indirect light transport planes (the emission's sweeps read the first plane
// of the four): one colour on both regions lights the volume as the same global colour does.
TEST(EmittedLight, RegionTransportPlanesLeaveTheEmittedLightAlone) {
    Scene s = glowingCoreScene(writeGlowingCore(tempDir("emitted_light_transport"), 1.0f, 4.0f));
    Light key;
    key.direction = glm::normalize(glm::vec3(-0.4f, 0.3f, -1.0f));
    s.lights = {key};
    TransferRegion shell, core;
    shell.value = {0.5f, 1.5f};
    shell.extinction = 1.0f;
    core.value = {3.5f, 4.5f};
    core.extinction = 4.0f;
    s.volume().material.transfer_2d = {shell, core};
    const glm::vec3 colour(0.9f, 0.6f, 0.4f);
    Indirect in;
    in.model = IndirectModel::Kniss;
    in.transport_color = colour;
    s.effects.indirect = in;
    Renderer global(s);
    global.prepare(std::nullopt, false);
    for (TransferRegion& r : s.volume().material.transfer_2d) r.transport = colour;
    s.effects.indirect->transport_color = glm::vec3(0.3f);
    Renderer regions(s);
    regions.prepare(std::nullopt, false);
    const std::vector<float>& a = global.lightingOutput<IlluminationVolume>()->values;
    const std::vector<float>& b = regions.lightingOutput<IlluminationVolume>()->values;
    ASSERT_EQ(a.size(), b.size());
    double peak = 0.0, error = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        ASSERT_TRUE(std::isfinite(b[i])) << i;
        peak = std::max(peak, double(std::abs(a[i])));
        error = std::max(error, double(std::abs(a[i] - b[i])));
    }
    EXPECT_GT(peak, 0.0);
    EXPECT_LE(error, 1e-5 * peak);
}

}  // namespace
}  // namespace voxlux::test
