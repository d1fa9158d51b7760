// Emission sources: the baked tables (constant, ramp, blackbody and its normalisations), the
// march's integration of emission against the analytic result, several grids of different
// topology, all-zero grids and real fire caches. The scene JSON's emission list: test_scene.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include <OpenColorIO/OpenColorIO.h>

#include "backend/backend_choice.h"
#include "optics/blackbody.h"
#include "optics/emission.h"
#include "render/renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

namespace OCIO = OCIO_NAMESPACE;
constexpr int kRows = VX_EMISSION_LUT_SIZE;
const glm::mat3 kIdentity(1.0f);   // bakes blackbody tables in XYZ

EmissionSource constant(glm::vec3 color, float intensity) {
    EmissionSource e;
    e.color = color;
    e.intensity = intensity;
    return e;
}

// Kelvin = value * scale: over grid values [0, 255] the table's row i is at i * scale kelvin.
EmissionSource blackbody(float scale, BlackbodyNormalization n, float intensity) {
    EmissionSource e;
    e.kind = EmissionKind::Blackbody;
    e.temperature_scale = scale;
    e.normalization = n;
    e.intensity = intensity;
    return e;
}

EmissionSource ramp(std::vector<RampPoint> points, float intensity) {
    EmissionSource e;
    e.kind = EmissionKind::Ramp;
    e.ramp = std::move(points);
    e.intensity = intensity;
    return e;
}

glm::vec3 row(const EmissionTable& t, int i) { return glm::vec3(t.rows[size_t(i)]); }

void expectNear(glm::vec3 a, glm::vec3 b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(EmissionTable, XyzToAcescgMapsD65WhiteToAcesWhite) {
    expectNear(kXyzD65ToAcescg * glm::vec3(0.95047f, 1.0f, 1.08883f), glm::vec3(1.0f), 1e-3f);
    // OpenColorIO's own construction, inverted, agrees column by column.
    auto bt = OCIO::BuiltinTransform::Create();
    bt->setStyle("UTILITY - ACES-AP1_to_CIE-XYZ-D65_BFD");
    bt->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
    auto cpu = OCIO::Config::CreateRaw()->getProcessor(bt)->getDefaultCPUProcessor();
    for (int c = 0; c < 3; ++c) {
        float xyz[3] = {0.0f, 0.0f, 0.0f};
        xyz[c] = 1.0f;
        cpu->applyRGB(xyz);
        expectNear(kXyzD65ToAcescg[c], glm::vec3(xyz[0], xyz[1], xyz[2]), 1e-5f);
    }
}

TEST(EmissionTable, ConstantIsValueTimesColourTimesIntensity) {
    const EmissionTable t = bakeEmission(constant({0.5f, 1.0f, 2.0f}, 3.0f), 2.0f, kXyzD65ToAcescg);
    ASSERT_EQ(t.rows.size(), size_t(kRows));
    for (int i : {0, 1, 100, 255}) expectNear(row(t, i), 2.0f * float(i) / 255.0f * glm::vec3(1.5f, 3.0f, 6.0f), 1e-6f);
    EXPECT_EQ(t.threshold, 0.0f);  // every value above 0 emits
}

TEST(EmissionTable, RampInterpolatesAndClamps) {
    const EmissionSource r = ramp({{0.0f, glm::vec3(0.0f)}, {51.0f, {1, 0, 0}}, {204.0f, {1, 1, 0}}}, 2.0f);
    const EmissionTable t = bakeEmission(r, 255.0f, kXyzD65ToAcescg);  // row i at value i
    expectNear(row(t, 0), glm::vec3(0.0f), 0.0f);
    expectNear(row(t, 17), glm::vec3(2.0f / 3.0f, 0.0f, 0.0f), 1e-6f);
    expectNear(row(t, 51), glm::vec3(2.0f, 0.0f, 0.0f), 1e-6f);
    expectNear(row(t, 102), glm::vec3(2.0f, 2.0f / 3.0f, 0.0f), 1e-6f);
    expectNear(row(t, 230), glm::vec3(2.0f, 2.0f, 0.0f), 0.0f);  // clamped above the last point
    // Black up to value 10: rows 0..10 are 0, so values up to row 10's emit nothing.
    const EmissionTable late = bakeEmission(ramp({{10.0f, glm::vec3(0.0f)}, {20.0f, glm::vec3(1.0f)}}, 1.0f), 255.0f,
                                            kXyzD65ToAcescg);
    for (int i = 0; i <= 10; ++i) EXPECT_EQ(row(late, i), glm::vec3(0.0f)) << i;
    EXPECT_GT(row(late, 11).x, 0.0f);
    EXPECT_EQ(late.threshold, 10.0f);
}

TEST(EmissionTable, BlackbodyLuminanceNormalisationHasYEqualToIntensity) {
    // Tables in XYZ (identity matrix): row i at 20 i kelvin.
    const EmissionTable t = bakeEmission(blackbody(20.0f, BlackbodyNormalization::Luminance, 2.5f), 255.0f, kIdentity);
    for (int i : {50, 75, 150, 255}) EXPECT_NEAR(row(t, i).y, 2.5f, 2.5e-6f) << i * 20 << " K";
    // Only the colour changes: redder (more X per Z) the cooler.
    EXPECT_GT(row(t, 50).x / row(t, 50).z, 10.0f * row(t, 255).x / row(t, 255).z);
    // In ACEScg a 1500 K flame is red, far more than blue.
    const glm::vec3 flame = kXyzD65ToAcescg * row(t, 75);
    EXPECT_GT(flame.x, flame.y);
    EXPECT_GT(flame.y, flame.z);
}

TEST(EmissionTable, BlackbodyPhysicalNormalisationFollowsPlanck) {
    EmissionSource s = blackbody(10.0f, BlackbodyNormalization::Physical, 3.0f);
    s.reference_temperature = 1000.0f;
    const EmissionTable t = bakeEmission(s, 255.0f, kIdentity);  // row i at 10 i kelvin
    EXPECT_NEAR(row(t, 100).y, 3.0f, 3e-6f);                      // 1000 K: the reference
    const double planck = blackbodyXYZ(2000.0).y / blackbodyXYZ(1000.0).y;
    EXPECT_NEAR(double(row(t, 200).y) / double(row(t, 100).y), planck, 1e-5 * planck);
    EXPECT_GT(planck, 100.0);  // far steeper than the luminance normalisation's 1
}

TEST(EmissionTable, BlackbodyBelowTheCutoffIsExactlyZero) {
    EmissionSource s = blackbody(10.0f, BlackbodyNormalization::Luminance, 1.0f);
    s.cutoff = 1234.0f;
    const EmissionTable t = bakeEmission(s, 255.0f, kXyzD65ToAcescg);
    for (int i = 0; i <= 123; ++i) ASSERT_EQ(row(t, i), glm::vec3(0.0f)) << i * 10 << " K";
    EXPECT_GT(row(t, 124).x, 0.0f);
    EXPECT_EQ(t.threshold, 123.0f);
    // An offset that puts low values at or below 0 K (row 50 at 0 K, row 150 at 1000 K).
    s.cutoff = 0.0f;
    s.temperature_offset = -500.0f;
    const EmissionTable offset = bakeEmission(s, 255.0f, kXyzD65ToAcescg);
    for (int i = 0; i <= 50; ++i) ASSERT_EQ(row(offset, i), glm::vec3(0.0f)) << i;
    EXPECT_GT(row(offset, 150).x, 0.0f);
}

TEST(EmissionTable, AllZeroTablesEmitNowhere) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(bakeEmission(constant(glm::vec3(1.0f), 1.0f), 0.0f, kXyzD65ToAcescg).threshold, inf);   // all-zero grid
    EXPECT_EQ(bakeEmission(constant(glm::vec3(1.0f), 0.0f), 5.0f, kXyzD65ToAcescg).threshold, inf);   // intensity 0
    EmissionSource cold = blackbody(1000.0f, BlackbodyNormalization::Physical, 1.0f);
    cold.cutoff = 1000.0f;
    EXPECT_EQ(bakeEmission(cold, 0.9f, kXyzD65ToAcescg).threshold, inf);  // never reaches the cutoff
}

// --- The march ---

constexpr int kN = 64;           // box edge in voxels
constexpr double kVoxel = 0.5;

// A grid of `value` over the box [lo, hi] of voxels.
openvdb::FloatGrid::ConstPtr boxOf(openvdb::Coord lo, openvdb::Coord hi, float value, const std::string& name) {
    auto g = boxGrid(lo, hi, value, kVoxel);
    g->setName(name);
    return g;
}

// No lights: the image is the emission alone.
Scene emissionScene(std::vector<EmissionSource> sources, float density_scale) {
    Scene s;
    s.render.width = 9;
    s.render.height = 9;
    s.volume().material.density_scale = density_scale;
    s.effects.shadows = ShadowMethod::None;
    s.volume().emission = std::move(sources);
    return s;
}

// Camera 200 world units from `target` looking down -z, narrow: pixel (4, 4) is the ray along
// -z through the target. Its distance to every voxel plane is a multiple of the step (a quarter
// voxel), so each sample segment lies on one linear piece of the reconstruction.
Camera cameraAbove(glm::vec3 target) {
    Camera c;
    c.look_at = target;
    c.position = target + glm::vec3(0.0f, 0.0f, 200.0f);
    c.fov = 1.0f;
    return c;
}

const kernel::VxPixel& centre(const RenderImage& img) { return img.pixels[4 * 9 + 4]; }

std::vector<std::unique_ptr<KernelBackend>> backends() {
    std::vector<std::unique_ptr<KernelBackend>> out;
    out.push_back(makeCpuBackend());
    if (auto gl = glBackendOrSkip()) out.push_back(std::move(gl));
    return out;
}

// A homogeneous emitting box, density and emission the same shape, seen through kN voxels: the
// reconstruction ramps both over one voxel outside each face alike, so emission per extinction
// is constant and L = e / sigma * (1 - exp(-tau)), tau = sigma * kN * voxel (e * kN * voxel
// without absorption). The march integrates each segment exactly, so only rounding remains.
TEST(EmissionRender, HomogeneousBoxMatchesTheAnalyticIntegral) {
    const glm::vec3 e(0.2f, 0.5f, 1.0f);
    const double length = kN * kVoxel;
    const glm::vec3 mid(float((kN - 1) * 0.5 * kVoxel));
    for (auto& backend : backends()) {
        for (float sigma : {0.0f, 0.05f}) {
            SCOPED_TRACE(backend->name() + ", sigma " + std::to_string(sigma));
            auto volume = volumeFromGrid(boxGrid({0, 0, 0}, {kN - 1, kN - 1, kN - 1}, 1.0f, kVoxel),
                                         {boxOf({0, 0, 0}, {kN - 1, kN - 1, kN - 1}, 1.0f, "temperature")});
            auto prepared = prepare(std::move(volume), emissionScene({constant(e, 1.0f)}, sigma), cameraAbove(mid));
            const kernel::VxPixel px = centre(backend->march(prepared->inputs));
            const double tau = sigma * length;
            const double per_unit = sigma > 0.0f ? (1.0 - std::exp(-tau)) / sigma : length;
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(px.emission[c], e[c] * per_unit, 1e-5 * e[c] * per_unit) << c;
            std::printf("  %s, sigma %g: emission B %.7g, analytic %.7g (relative error %.2g)\n", backend->name().c_str(),
                        double(sigma), double(px.emission.z), per_unit, std::abs(px.emission.z - per_unit) / per_unit);
            EXPECT_NEAR(px.transmittance, std::exp(-tau), 1e-6);
            EXPECT_EQ(glm::vec3(px.rgba), px.emission);  // no lights: the beauty is the emission
        }
    }
}

// Two grids of disjoint topology: the atlas holds the union of their bricks, each channel is
// zero on the other's bricks, and each box glows in its own source's colour only.
TEST(EmissionRender, TwoSourcesOfDifferentTopologyEmitOnlyTheirOwnColour) {
    auto red = boxOf({0, 0, 0}, {15, 15, 15}, 1.0f, "flame");
    auto blue = boxOf({48, 0, 0}, {63, 15, 15}, 2.0f, "heat");
    const Scene scene = emissionScene(
        {constant({1, 0, 0}, 1.0f), ramp({{0.0f, glm::vec3(0.0f)}, {2.0f, {0, 0, 1}}}, 1.0f)}, 0.0f);
    auto seenFrom = [&](const Camera& camera) {  // no density at all
        return prepare(volumeFromGrid(boxGrid({0, 0, 0}, {-1, -1, -1}, 0.0f, kVoxel), {red, blue}), scene, camera);
    };
    auto prepared = seenFrom(Camera{});
    const BrickAtlas& atlas = prepared->atlas;
    std::set<std::array<int, 3>> bricks;
    for (const auto& c : atlas.coords) bricks.insert({c.x, c.y, c.z});
    ASSERT_EQ(atlas.emission_sources, 2u);
    ASSERT_EQ(atlas.emission.size(), 2 * atlas.slots() * VX_BRICK_VOXELS);
    size_t red_bricks = 0, blue_bricks = 0;
    for (size_t i = 0; i < atlas.slots(); ++i) {
        const float r = atlas.emission_max[i], b = atlas.emission_max[atlas.slots() + i];
        EXPECT_FALSE(r > 0.0f && b > 0.0f) << "brick " << i << " holds both boxes";
        red_bricks += r > 0.0f;
        blue_bricks += b > 0.0f;
    }
    // Each box spans 2^3 bricks; with its - side neighbours, whose aprons reach it, 3^3 hold some.
    EXPECT_EQ(red_bricks, 27u);
    EXPECT_EQ(blue_bricks, 27u);
    for (const auto& grid : {red, blue})
        for (auto it = grid->cbeginValueOn(); it; ++it)
            ASSERT_TRUE(bricks.count({it.getCoord().x() >> 3, it.getCoord().y() >> 3, it.getCoord().z() >> 3}));
    EXPECT_EQ(prepared->pages.occupied, atlas.slots());  // every brick emits from one source

    const double length = 16 * kVoxel;
    for (auto& backend : backends()) {
        SCOPED_TRACE(backend->name());
        for (bool left : {true, false}) {
            const glm::vec3 target = glm::vec3(left ? 7.5f : 55.5f, 7.5f, 7.5f) * float(kVoxel);
            const kernel::VxPixel px = centre(backend->march(seenFrom(cameraAbove(target))->inputs));
            EXPECT_NEAR(px.emission.x, left ? length : 0.0, 1e-4 * length);
            EXPECT_EQ(px.emission.y, 0.0f);
            EXPECT_NEAR(px.emission.z, left ? 0.0 : length, 1e-4 * length);
            EXPECT_EQ(left ? px.emission.z : px.emission.x, 0.0f);  // exactly: the other grid is 0 here
        }
    }
}

// All-zero temperature beside density: no emission at all, and the image is the one without
// emission to the bit. Without density the frame is empty.
TEST(EmissionRender, AllZeroTemperatureEmitsNothing) {
    EmissionSource fire = blackbody(1000.0f, BlackbodyNormalization::Physical, 1.0f);
    fire.grid.name = "temperature";
    auto density = boxGrid({0, 0, 0}, {23, 23, 23}, 1.0f, kVoxel);
    auto cold = boxOf({-8, -8, -8}, {31, 31, 31}, 0.0f, "temperature");   // active, all 0, larger
    Scene lit = emissionScene({fire}, 0.4f);
    lit.render.width = lit.render.height = 24;
    lit.effects.shadows = ShadowMethod::Raymarch;
    Light key;
    key.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
    key.intensity = 3.0f;
    lit.lights = {key};
    Scene plain = lit;
    plain.volume().emission.clear();
    Camera camera;
    camera.position = glm::vec3(20.0f, 12.0f, 25.0f);
    camera.look_at = glm::vec3(6.0f);
    for (auto& backend : backends()) {
        SCOPED_TRACE(backend->name());
        auto with = prepare(volumeFromGrid(density, {cold}), lit, camera);
        auto without = prepare(volumeFromGrid(density), plain, camera);
        EXPECT_EQ(with->inputs.params.emission_sources, 0);
        const RenderImage a = backend->march(with->inputs), b = backend->march(without->inputs);
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        float alpha = 0.0f;
        for (size_t i = 0; i < a.pixels.size(); ++i) {
            ASSERT_EQ(a.pixels[i].emission, glm::vec3(0.0f));
            ASSERT_EQ(a.pixels[i].rgba, b.pixels[i].rgba) << i;
            ASSERT_EQ(a.pixels[i].depth, b.pixels[i].depth) << i;
            alpha = std::max(alpha, a.pixels[i].rgba.w);
        }
        EXPECT_GT(alpha, 0.5f);
    }

    // Zero density and zero temperature in a file: nothing visible, an empty frame, and why.
    const std::string file = tempDir("emission") + "/cold.vdb";
    openvdb::io::File(file).write({boxGrid({0, 0, 0}, {7, 7, 7}, 0.0f, kVoxel), cold});
    Scene s = lit;
    s.volume().path = file;
    s.render.backend = Backend::Cpu;
    s.camera = camera;
    const FrameResult r = Renderer(s).render(std::nullopt, true);
    EXPECT_TRUE(r.empty);
    EXPECT_EQ(r.bricks, 0u);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_EQ(r.warnings[0], file + ": grid 'density' has nothing visible: its 512 active voxels are all zero under the "
                                    "material; emission from 'temperature' emits nothing; rendered as an empty frame");
    for (const auto& px : r.image.pixels) ASSERT_EQ(px.rgba, glm::vec4(0.0f));
}

// --- Real fire caches ---

// The emission AOV over the image: finite everywhere; returns the sum.
glm::dvec3 emissionSum(const RenderImage& img) {
    glm::dvec3 sum(0.0);
    for (const auto& px : img.pixels) {
        EXPECT_TRUE(std::isfinite(px.emission.x + px.emission.y + px.emission.z));
        sum += glm::dvec3(px.emission);
    }
    return sum;
}

// Blender (Mantaflow) fire: blackbody from temperature (about 0..3: 1500 K at ignition) plus a
// ramp from flame, on grids of their own topology.
TEST(EmissionFire, BlenderFireGlowsFromTemperatureAndFlame) {
    VOXLUX_REQUIRE_SHARED(fire, "blender/fire/fluid_data_0040.vdb");
    Scene s = parseScene(R"({"volume": {"path": ")" + fire + R"("},
        "material": {"density_scale": 20},
        "render": {"resolution": [48, 64], "backend": "cpu"},
        "emission": [
          {"grid": "temperature", "kind": "blackbody", "temperature_scale": 1000, "cutoff": 1000,
           "normalization": "physical", "reference_temperature": 1500},
          {"grid": "flame", "kind": "ramp", "intensity": 0.5,
           "ramp": [{"value": 0, "color": [0, 0, 0]}, {"value": 0.5, "color": [1, 0.3, 0.05]}, {"value": 1, "color": [1, 0.8, 0.5]}]}]})",
                         "fire.json", "");
    const FrameResult r = Renderer(s).render(std::nullopt, false);
    const glm::dvec3 sum = emissionSum(r.image);
    std::printf("  fire emission sum (%.4g, %.4g, %.4g)\n", sum.x, sum.y, sum.z);
    EXPECT_GT(sum.x, 0.0);
    EXPECT_GT(sum.x, 2.0 * sum.z);  // a 1500-3000 K fire is red-orange

    // The bricks cover every brick of flame (and temperature), whatever density's topology.
    const LoadedVolume v = loadVolume(fire, s.volume());
    const BrickAtlas atlas = buildBrickAtlas(v);
    std::set<std::array<int, 3>> bricks;
    for (const auto& c : atlas.coords) bricks.insert({c.x, c.y, c.z});
    for (const auto& grid : v.emission) {
        size_t missing = 0;
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            missing += !bricks.count({c.x() >> 3, c.y() >> 3, c.z() >> 3});
        }
        EXPECT_EQ(missing, 0u) << grid->getName();
    }
    std::printf("  temperature max %.3g, flame max %.3g\n", atlas.emissionGridMax(0), atlas.emissionGridMax(1));
    EXPECT_GT(atlas.emissionGridMax(0), 1.5f);   // above ignition somewhere
}

// OpenUSD's densityAndHeat: heat 0..0.76 on voxels that are not cubes.
TEST(EmissionFire, DensityAndHeatGlowsAsBlackbody) {
    VOXLUX_REQUIRE_SHARED(file, "openusd/densityAndHeat.vdb");
    Scene s;
    s.volume().path = file;
    s.render.width = s.render.height = 48;
    s.render.backend = Backend::Cpu;
    EmissionSource heat = blackbody(4000.0f, BlackbodyNormalization::Luminance, 2.0f);  // up to ~3000 K
    heat.grid.name = "heat";
    heat.cutoff = 800.0f;
    s.volume().emission = {heat};
    const FrameResult r = Renderer(s).render(std::nullopt, false);
    const glm::dvec3 sum = emissionSum(r.image);
    std::printf("  densityAndHeat emission sum (%.4g, %.4g, %.4g)\n", sum.x, sum.y, sum.z);
    EXPECT_GT(sum.x, 0.0);
    EXPECT_GT(sum.x, sum.z);
}

}  // namespace
}  // namespace voxlux::test
