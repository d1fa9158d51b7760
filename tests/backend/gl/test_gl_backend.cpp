// The GL backend against the CPU backend on small synthetic volumes. Both run the one kernel source
// (shaders/vx_*.h), so the images may differ only by float rounding: the GPU's exp/log/sqrt, and
// where each compiler fuses multiply-adds.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <utility>

#include "backend/backend_choice.h"
#include "scene/camera.h"
#include "gl/gl_context.h"
#include "gl/gl_program.h"
#include "lighting/extinction_sat/extinction_sat_stages.h"
#include "render/renderer.h"
#include "kernel/shader_source.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

// A box of constant density (crossing the origin, so brick coordinates go negative) beside a
// sphere of smooth noise, on a 0.1-unit grid.
constexpr int kSphereRadius = 12;
const Coord kSphereCentre(22, 4, 8);

float noise(const Coord& c) {
    return 0.5f + 0.5f * std::sin(0.7f * float(c.x())) * std::sin(0.9f * float(c.y()) + 1.0f) *
                      std::cos(0.8f * float(c.z()));
}

// Calls f(coord, r) for every voxel of the sphere, r = distance from the centre / radius.
template <typename F>
void forSphere(F f) {
    const Coord r(kSphereRadius);
    for (auto it = CoordBBox(kSphereCentre - r, kSphereCentre + r).begin(); it; ++it) {
        const Coord d = *it - kSphereCentre;
        float dist = std::sqrt(float(d.x() * d.x() + d.y() * d.y() + d.z() * d.z())) / float(kSphereRadius);
        if (dist <= 1.0f) f(*it, dist);
    }
}

// With `emission_and_color`, an emission grid (the scene's one source, emissionSource()) and a
// colour grid over the sphere.
LoadedVolume makeVolume(bool emission_and_color) {
    auto density = boxGrid(Coord(-16, -8, -4), Coord(7, 15, 19), 1.0f, 0.1);
    auto acc = density->getAccessor();
    forSphere([&](const Coord& c, float r) { acc.setValue(c, 2.0f * noise(c) * (1.0f - r)); });
    if (!emission_and_color) return volumeFromGrid(density);
    auto emission = openvdb::FloatGrid::create(0.0f);
    auto color = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.0f));
    emission->setTransform(density->transform().copy());
    color->setTransform(density->transform().copy());
    auto eacc = emission->getAccessor();
    auto cacc = color->getAccessor();
    forSphere([&](const Coord& c, float r) {
        eacc.setValue(c, std::max(0.0f, 1.0f - 2.0f * r) * noise(c + Coord(5)));
        cacc.setValue(c, openvdb::Vec3s(1.0f - r, noise(c), r));
    });
    return volumeFromGrid(density, {emission}, color);
}

// A second emission grid, over part of the box: a topology of its own.
openvdb::FloatGrid::Ptr flameGrid() {
    auto g = boxGrid(Coord(-16, -8, -4), Coord(-5, 15, 19), 0.0f, 0.1);
    g->setName("flame");
    for (auto it = g->beginValueOn(); it; ++it) it.setValue(noise(it.getCoord() + Coord(11)));
    return g;
}

EmissionSource emissionSource() {
    EmissionSource e;
    e.color = glm::vec3(1.0f, 0.5f, 0.2f);
    e.intensity = 4.0f;
    return e;
}

Light directionalLight() {
    Light l;
    l.type = LightType::Directional;
    l.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, -0.3f));
    l.color = glm::vec3(1.0f, 0.95f, 0.9f);
    l.intensity = 3.0f;
    return l;
}

Light pointLight() {
    Light l;
    l.type = LightType::Point;
    l.position = glm::vec3(1.2f, 1.0f, 1.0f);   // just inside the sphere's edge, facing the box
    l.color = glm::vec3(0.6f, 0.8f, 1.0f);
    l.intensity = 2.0f;
    return l;
}

Light spotLight() {
    Light l;
    l.type = LightType::Spot;
    l.position = glm::vec3(-3.0f, 3.0f, 4.0f);
    l.direction = glm::normalize(glm::vec3(0.6f, -0.5f, -0.5f));
    l.intensity = 40.0f;
    l.cone_angle = 20.0f;
    l.cone_softness = 8.0f;
    return l;
}

Scene baseScene() {
    Scene s;
    s.render.width = 74;    // not a multiple of the 8x8 work group
    s.render.height = 66;   // more rows than one GL dispatch band (64)
    s.material.density_scale = 2.0f;   // extinction per world unit: the box is ~5 optical depths deep
    s.material.anisotropy = 0.3f;
    s.effects.shadows = ShadowMethod::Raymarch;
    s.lights = {directionalLight(), pointLight()};
    return s;
}

struct Renders {
    RenderImage cpu, gl;
};

// Both backends on the same volume, each through the whole render graph, as a render on it would
// run: each builds its own light cache and illumination volume. The camera is the default framing
// moved in, so the volume reaches the image's edges and every dispatch band has something to get
// wrong.
Renders renderBoth(LoadedVolume volume, Scene scene, KernelBackend& gl) {
    const CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    glm::vec3 lo, hi;
    worldBounds(volume.index_to_world, glm::vec3(box.min().x(), box.min().y(), box.min().z()),
                glm::vec3(box.max().x() + 1, box.max().y() + 1, box.max().z() + 1), lo, hi);
    Camera camera = frameBox(lo, hi, 40.0f, float(scene.render.width) / float(scene.render.height));
    camera.position = glm::mix(camera.look_at, camera.position, 0.45f);
    scene.camera = camera;
    auto cpu = makeCpuBackend();
    return {Renderer(scene, volume, *cpu).render(std::nullopt, false).image,
            Renderer(scene, volume, gl).render(std::nullopt, false).image};
}

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
    s.emission = {EmissionSource{}};   // white, for makeVolume(true)
    return s;
}

// AOV channels as float ranges of VxPixel (rgba, direct, ambient, emission, indirect, transmittance,
// depth; the trailing sample count is a cost, not an image, and is not compared).
// Depth is an opacity-weighted mean, a ratio of two tiny numbers where alpha is tiny (alpha 4e-6
// turns a 1-ulp difference in T into 3e-3 of depth), so it is compared where alpha >= 1e-3 only.
struct Channel {
    const char* name;
    int first, count;
    float min_alpha;
};
enum ChannelId { kRgba, kDirect, kAmbient, kEmission, kIndirect, kTransmittance, kDepth, kChannelCount };
constexpr Channel kChannels[kChannelCount] = {{"rgba", 0, 4, 0.0f},
                                              {"direct", 4, 3, 0.0f},
                                              {"ambient", 7, 3, 0.0f},
                                              {"emission", 10, 3, 0.0f},
                                              {"indirect", 13, 3, 0.0f},
                                              {"transmittance", 16, 1, 0.0f},
                                              {"depth", 17, 1, 1e-3f}};
static_assert(offsetof(kernel::VxPixel, indirect) == 13 * sizeof(float) &&
              offsetof(kernel::VxPixel, transmittance) == 16 * sizeof(float) &&
              offsetof(kernel::VxPixel, depth) == 17 * sizeof(float));

// Tolerances, relative to the CPU channel's scale. The backends differ only by float rounding
// (log/sqrt implementations, FMA contraction). Measured on llvmpipe: RMSE <= 1.5e-6 of the mean,
// max abs <= 4.1e-6 of the peak (each run prints them). 1e-4 leaves room for that and for a GPU's
// approximate log/sqrt, while a sample taken by one backend and skipped by the other at a brick
// boundary (~1e-2) still fails.
constexpr double kRmseOfMean = 1e-4;
constexpr double kMaxAbsOfPeak = 1e-4;

float component(const kernel::VxPixel& p, int i) { return reinterpret_cast<const float*>(&p)[i]; }

struct ChannelStats {
    double rmse = 0.0, max_abs = 0.0;  // GL - CPU
    double mean = 0.0, peak = 0.0;     // of |CPU|
};

ChannelStats compare(const RenderImage& cpu, const RenderImage& gl, const Channel& ch) {
    ChannelStats s;
    double sum_sq = 0.0, sum_ref = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) {
        if (cpu.pixels[i].rgba.w < ch.min_alpha) continue;
        for (int k = ch.first; k < ch.first + ch.count; ++k, ++n) {
            const double ref = component(cpu.pixels[i], k), d = component(gl.pixels[i], k) - ref;
            sum_sq += d * d;
            sum_ref += std::abs(ref);
            s.max_abs = std::max(s.max_abs, std::abs(d));
            s.peak = std::max(s.peak, std::abs(ref));
        }
    }
    s.rmse = n ? std::sqrt(sum_sq / double(n)) : 0.0;
    s.mean = n ? sum_ref / double(n) : 0.0;
    return s;
}

// Checks every channel against the tolerances and returns the statistics for further checks.
std::array<ChannelStats, kChannelCount> expectMatch(const Renders& r) {
    std::array<ChannelStats, kChannelCount> stats;
    EXPECT_EQ(r.gl.width, r.cpu.width);
    EXPECT_EQ(r.gl.height, r.cpu.height);
    if (r.gl.pixels.size() != r.cpu.pixels.size()) {
        ADD_FAILURE() << "GL image has " << r.gl.pixels.size() << " pixels, CPU " << r.cpu.pixels.size();
        return stats;
    }
    for (int c = 0; c < kChannelCount; ++c) {
        const ChannelStats& s = stats[c] = compare(r.cpu, r.gl, kChannels[c]);
        EXPECT_LE(s.rmse, kRmseOfMean * s.mean) << kChannels[c].name << ": mean |cpu| " << s.mean;
        EXPECT_LE(s.max_abs, kMaxAbsOfPeak * s.peak) << kChannels[c].name << ": peak |cpu| " << s.peak;
        // The measured agreement, which docs/architecture.md quotes.
        std::printf("  %-13s rmse/mean %.2g  max/peak %.2g\n", kChannels[c].name, s.mean > 0 ? s.rmse / s.mean : 0.0,
                    s.peak > 0 ? s.max_abs / s.peak : 0.0);
    }
    // Not vacuous: the volume is in view and partly opaque.
    EXPECT_GT(stats[kRgba].peak, 0.5);
    return stats;
}

TEST(GlBackend, NameNamesTheRenderer) {
    VOXLUX_REQUIRE_GL(gl);
    EXPECT_EQ(gl->name().rfind("gl (", 0), 0u) << gl->name();
}

TEST(GlBackend, MatchesCpuWithShadowedDirectionalAndPointLights) {
    VOXLUX_REQUIRE_GL(gl);
    const auto stats = expectMatch(renderBoth(makeVolume(false), baseScene(), *gl));
    EXPECT_GT(stats[kDirect].peak, 0.0);
    EXPECT_EQ(stats[kEmission].peak, 0.0);
}

// Unshadowed directional light only: the march takes its telescoped per-batch path.
TEST(GlBackend, MatchesCpuWithUnshadowedDirectionalLight) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.effects.shadows = ShadowMethod::None;
    scene.lights = {directionalLight()};
    EXPECT_GT(expectMatch(renderBoth(makeVolume(false), scene, *gl))[kDirect].peak, 0.0);
}

TEST(GlBackend, MatchesCpuWithEmissionAndColourGrids) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.emission = {emissionSource()};
    const auto stats = expectMatch(renderBoth(makeVolume(true), scene, *gl));
    EXPECT_GT(stats[kDirect].peak, 0.0);
    EXPECT_GT(stats[kEmission].peak, 0.0);
}

// Two sources on grids of different topology: a blackbody from the sphere's grid (its 0..1 up to
// 3000 K) and a ramp from the flame grid.
TEST(GlBackend, MatchesCpuWithTwoEmissionSources) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    EmissionSource fire;
    fire.kind = EmissionKind::Blackbody;
    fire.temperature_scale = 3000.0f;
    fire.cutoff = 600.0f;
    fire.normalization = BlackbodyNormalization::Physical;
    fire.intensity = 2.0f;
    EmissionSource flame;
    flame.kind = EmissionKind::Ramp;
    flame.ramp = {{0.0f, glm::vec3(0.0f)}, {0.5f, {1.0f, 0.3f, 0.05f}}, {1.0f, {1.0f, 0.9f, 0.6f}}};
    flame.intensity = 3.0f;
    scene.emission = {fire, flame};
    LoadedVolume volume = makeVolume(true);
    volume.emission.push_back(flameGrid());
    const auto stats = expectMatch(renderBoth(std::move(volume), scene, *gl));
    EXPECT_GT(stats[kDirect].peak, 0.0);
    EXPECT_GT(stats[kEmission].peak, 0.0);
}

TEST(GlBackend, MatchesCpuWithTransferFunction) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.lights.push_back(spotLight());
    scene.material.transfer = {{0.1f, 0.0f, glm::vec3(1.0f)},
                               {0.5f, 1.5f, glm::vec3(1.0f, 0.6f, 0.3f)},
                               {1.2f, 0.4f, glm::vec3(0.3f, 0.5f, 1.0f)}};
    EXPECT_GT(expectMatch(renderBoth(makeVolume(false), scene, *gl))[kDirect].peak, 0.0);
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
    const LightCache &c = *on_cpu.lightCache(), &g = *on_gl.lightCache();
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

// Propagation shadows with indirect light (Kniss's transport colour, and the diffusion model of a
// coloured albedo), the eye pass, chroma subsampling, perturbation and surface shading: the
// illumination volume is swept by each backend, then marched, and read trilinearly and by the
// B-spline.
TEST(GlBackend, MatchesCpuWithPropagation) {
    VOXLUX_REQUIRE_GL(gl);
    for (IndirectModel model : {IndirectModel::Kniss, IndirectModel::Diffusion}) {
        Scene s = baseScene();
        s.effects.shadows = ShadowMethod::Propagation;
        s.effects.light_resolution = 24;
        Indirect in;
        in.model = model;
        in.transport_color = glm::vec3(1.0f, 0.6f, 0.35f);
        s.material.albedo = glm::vec3(0.95f, 0.8f, 0.6f);
        s.effects.indirect = in;
        s.effects.propagation.eye_pass = true;
        s.effects.propagation.chroma_subsampling = true;
        // Each read of the illumination volume once: the B-spline with the diffusion model.
        s.effects.propagation.filter = model == IndirectModel::Kniss ? Filter::Trilinear : Filter::Tricubic;
        Perturbation p;
        p.density = 0.6f;
        p.transport = 0.3f;
        p.displacement = 1.0f;
        s.effects.perturbation = p;
        s.effects.surface = SurfaceShading{};
        s.lights = {directionalLight(), pointLight(), spotLight()};
        s.emission = {EmissionSource{}};
        const auto stats = expectMatch(renderBoth(makeVolume(true), s, *gl));
        EXPECT_GT(stats[kDirect].peak, 0.0);
        EXPECT_GT(stats[kIndirect].peak, 0.0);
    }
}

// Emission lighting the medium with no light at all: the source sweeps alone fill the indirect
// block (unperturbed, so the CPU runs its row batches and GL the per-cell kernel).
TEST(GlBackend, MatchesCpuWithEmissionLightingTheMedium) {
    VOXLUX_REQUIRE_GL(gl);
    Scene s = baseScene();
    s.lights.clear();
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.light_resolution = 24;
    s.effects.indirect = Indirect{};
    s.material.albedo = glm::vec3(0.9f, 0.7f, 0.5f);
    s.emission = {emissionSource()};
    const auto stats = expectMatch(renderBoth(makeVolume(true), s, *gl));
    EXPECT_GT(stats[kIndirect].peak, 0.0);
    EXPECT_EQ(stats[kDirect].peak, 0.0);
}

TEST(GlBackend, MatchesCpuWithoutLights) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.lights.clear();
    scene.emission = {emissionSource()};
    const auto stats = expectMatch(renderBoth(makeVolume(true), scene, *gl));
    EXPECT_EQ(stats[kDirect].peak, 0.0);
    EXPECT_EQ(stats[kDirect].max_abs, 0.0);
    EXPECT_GT(stats[kEmission].peak, 0.0);
}

// OCIO's text goes between vx_grade.h and grade.comp; a compile error names the program and
// carries the driver's log.
TEST(GlBackend, GradeShaderErrorsCarryTheLog) {
    VOXLUX_REQUIRE_GL(gl);
    ensureGlContext();
    const GLuint program =
        compileComputeProgram(assembleGradeShader("vec4 ocio_transform(vec4 c) { return c; }"), "grade");
    EXPECT_NE(program, 0u);
    glDeleteProgram(program);
    try {
        compileComputeProgram(assembleGradeShader("vec4 ocio_transform(vec4 c) { return c }"), "broken grade");
        ADD_FAILURE() << "a missing semicolon compiled";
    } catch (const std::runtime_error& e) {
        const std::string message = e.what(), heading = "GL compute shader broken grade does not compile:\n";
        EXPECT_EQ(message.rfind(heading, 0), 0u) << message;
        EXPECT_GT(message.size(), heading.size()) << "no log: " << message;
    }
}

}  // namespace
}  // namespace voxlux::test
