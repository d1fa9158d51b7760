// Analytic checks of the march: transmittance through a homogeneous box equals exp(-sigma * d),
// on both backends, for an axis-aligned and a diagonal ray; stability on hard inputs.
#include <algorithm>
#include <cmath>

#include "backend/backend_choice.h"
#include "scene/camera.h"
#include "kernel/cpu_kernel.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kN = 64;          // box edge in voxels
constexpr double kVoxel = 0.5;  // non-unit voxel size on purpose

// Trilinear reconstruction ramps the box to zero over one voxel outside each face, so a ray that
// enters and leaves through the two faces across its dominant axis a sees exactly kN voxels of
// density along a: tau = sigma * kN * voxel / |dir.a|.
double expectedTau(float sigma, glm::vec3 dir) {
    glm::vec3 a = glm::abs(dir);
    return double(sigma) * kN * kVoxel / std::max({a.x, a.y, a.z});
}

Scene boxScene(float step) {
    Scene s;
    s.render.width = 9;
    s.render.height = 9;
    s.render.step = step;
    s.effects.shadows = ShadowMethod::None;
    return s;
}

// Camera 200 world units from the box centre, looking along `dir`: pixel (4, 4) is that ray.
Camera cameraOnBox(glm::vec3 dir) {
    return cameraAlong(glm::vec3(float((kN - 1) * 0.5 * kVoxel)), dir, 200.0f, 1.0f);
}

struct Case {
    glm::vec3 dir;
    float step;
};

void checkBox(KernelBackend& backend, const Case& c, float sigma) {
    auto prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {kN - 1, kN - 1, kN - 1}, sigma, kVoxel)),
                            boxScene(c.step), cameraOnBox(c.dir));
    RenderImage img = backend.march(prepared->inputs);
    const auto& px = img.pixels[4 * 9 + 4];
    const double expected = std::exp(-expectedTau(sigma, glm::normalize(c.dir)));
    EXPECT_NEAR(px.transmittance, expected, 1e-4) << backend.name() << " dir " << c.dir.x << "," << c.dir.y;
    EXPECT_NEAR(px.rgba.w, 1.0 - expected, 1e-4);
}

// Axis-aligned: a step dividing the voxel puts every ramp kink at the same sample phase, so the
// midpoint rule is exact. Diagonal: kinks fall at varying phases; the midpoint error per kink is
// at most sigma * h^2 / 8 for sample spacing h along x, so step 0.1 keeps |dT| < 1e-5 here.
const Case kCases[] = {{{1, 0, 0}, 0.5f}, {{0, 0, -1}, 0.5f}, {{1, 0.3f, 0.2f}, 0.1f}, {{-0.8f, -0.25f, 0.3f}, 0.1f}};

TEST(Transmittance, HomogeneousBoxCpu) {
    auto cpu = makeCpuBackend();
    for (const auto& c : kCases)
        for (float sigma : {0.01f, 0.05f}) checkBox(*cpu, c, sigma);
}

TEST(Transmittance, HomogeneousBoxGl) {
    VOXLUX_REQUIRE_GL(gl);
    for (const auto& c : kCases)
        for (float sigma : {0.01f, 0.05f}) checkBox(*gl, c, sigma);
}

// Any affine index-to-world transform: anisotropic scale, rotation and translation. A ray along
// the grid's index x axis crosses kN index units, i.e. kN * |A e_x| world units.
TEST(Transmittance, AffineTransformCpuAndGl) {
    const float sigma = 0.02f;
    auto g = boxGrid({0, 0, 0}, {kN - 1, kN - 1, kN - 1}, sigma);
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    m.preScale(openvdb::Vec3d(0.5, 1.0, 2.0));
    m.postRotate(openvdb::math::Z_AXIS, 0.5);
    m.postRotate(openvdb::math::X_AXIS, -0.3);
    m.postTranslate(openvdb::Vec3d(3.0, -7.0, 11.0));
    g->setTransform(openvdb::math::Transform::createLinearTransform(m));
    const LoadedVolume volume = volumeFromGrid(g);
    const glm::vec3 axis = glm::vec3(volume.index_to_world[0]);
    const glm::vec3 centre = glm::vec3(volume.index_to_world * glm::vec4(glm::vec3((kN - 1) * 0.5f), 1.0f));
    Camera camera;
    camera.look_at = centre;
    camera.position = centre - glm::normalize(axis) * 300.0f;
    camera.fov = 1.0f;
    const double expected = std::exp(-double(sigma) * kN * glm::length(axis));
    std::vector<std::unique_ptr<KernelBackend>> backends;
    backends.push_back(makeCpuBackend());
    if (auto gl = glBackendOrSkip()) backends.push_back(std::move(gl));
    for (auto& backend : backends) {
        auto prepared = prepare(volume, boxScene(0.5f), camera);
        const kernel::VxPixel px = backend->march(prepared->inputs).pixels[4 * 9 + 4];  // a copy: the image is a temporary
        EXPECT_NEAR(px.transmittance, expected, 1e-4) << backend->name();
    }
}

TEST(Stability, DenseMediumIsOpaqueAndFinite) {
    auto prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {31, 31, 31}, 1e6f)), boxScene(0.5f), cameraOnBox({1, 0, 0}));
    RenderImage img = makeCpuBackend()->march(prepared->inputs);
    const auto& px = img.pixels[4 * 9 + 4];
    EXPECT_LT(px.transmittance, 1e-30f);  // e^-87, where the kernel's exponential saturates
    EXPECT_EQ(px.rgba.w, 1.0f);
}

TEST(Stability, NanAndNegativeVoxelsAreCountedAndZeroed) {
    auto g = boxGrid({0, 0, 0}, {15, 15, 15}, 0.1f);
    auto acc = g->getAccessor();
    acc.setValue({3, 3, 3}, std::nanf(""));
    acc.setValue({4, 4, 4}, INFINITY);
    acc.setValue({5, 5, 5}, -2.0f);
    Scene scene = boxScene(0.5f);
    scene.lights.push_back(defaultKeyLight());
    scene.effects.shadows = ShadowMethod::Raymarch;
    auto prepared = prepare(volumeFromGrid(g), scene, cameraOnBox({1, 0.2f, 0.1f}));
    EXPECT_EQ(prepared->atlas.density_fixes.non_finite, 2u);
    EXPECT_EQ(prepared->atlas.density_fixes.negative, 1u);
    for (float v : prepared->atlas.density) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
    RenderImage img = makeCpuBackend()->march(prepared->inputs);
    for (const auto& px : img.pixels)
        for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(px.rgba[k]));
}

TEST(Stability, PointLightInsideAndOnFaceStaysFinite) {
    auto g = boxGrid({0, 0, 0}, {31, 31, 31}, 0.2f);
    Scene scene = boxScene(0.5f);
    scene.effects.shadows = ShadowMethod::Raymarch;
    for (glm::vec3 pos : {glm::vec3(15.5f), glm::vec3(0.0f, 15.5f, 15.5f), glm::vec3(16.0f, 16.0f, 16.0f)}) {
        Light l;
        l.type = LightType::Point;
        l.position = pos;
        l.intensity = 1e6f;  // HDR
        scene.lights = {l};
        auto prepared = prepare(volumeFromGrid(g), scene, cameraOnBox({1, 0.1f, 0.05f}));
        RenderImage img = makeCpuBackend()->march(prepared->inputs);
        float peak = 0.0f;
        for (const auto& px : img.pixels) {
            for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(px.rgba[k]));
            peak = std::max(peak, px.rgba.x);
        }
        EXPECT_GT(peak, 0.0f);
    }
}

// The brute-force shadow of a directional light through a slab: single scattering at one
// sample, checked against exp(-sigma * depth) by evaluating the kernel's shadow ray directly.
TEST(Shadows, SlabShadowRayMatchesBeerLambert) {
    const float sigma = 0.1f;
    auto prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {63, 63, 63}, sigma)), boxScene(0.5f),
                            cameraOnBox({1, 0, 0}));
    kernel::CpuKernel k;
    k.P = prepared->inputs.params;
    k.density = prepared->atlas.density;
    k.page = prepared->pages.entries;
    // From the centre of the box straight up (+y): 32 voxels of full density, then the ramp that
    // adds half a voxel, so depth = 63 - 31.5 + 0.5 = 32.
    float T = k.vx_shadow_transmittance(glm::vec3(31.5f), glm::vec3(0, 1, 0), 1e30f, VX_ALL_LINKS);
    EXPECT_NEAR(T, std::exp(-sigma * 32.0f), 1e-4);
}

}  // namespace
}  // namespace voxlux::test

namespace voxlux::test {
namespace {

// The kernel's own exponential (vectorisable on the CPU, identical on the GPU) against libm.
TEST(KernelMath, ExpIsAccurateOverTheWholeRange) {
    kernel::CpuKernel k;
    double worst = 0.0;
    for (double x = -87.0; x <= 0.0; x += 1e-3) {
        const float xf = float(x);
        const double exact = std::exp(double(xf));
        worst = std::max(worst, std::abs(double(k.vx_exp(xf)) - exact) / exact);
    }
    EXPECT_LT(worst, 3e-7);
    EXPECT_EQ(k.vx_exp(0.0f), 1.0f);
    EXPECT_EQ(k.vx_exp(-1e30f), k.vx_exp(-87.0f));  // clamped: finite and positive
    EXPECT_GT(k.vx_exp(-1e30f), 0.0f);
}

}  // namespace
}  // namespace voxlux::test

namespace voxlux::test {
namespace {

// The telescoped per-batch lighting (unshadowed directional light only) and the per-sample path
// integrate the same thing: adding a black point light forces the per-sample path.
TEST(March, TelescopedLightingEqualsPerSampleLighting) {
    auto g = boxGrid({0, 0, 0}, {40, 30, 20}, 0.08f);
    g->denseFill(openvdb::CoordBBox({10, 5, 5}, {20, 25, 15}), 0.5f, true);
    Scene scene = boxScene(0.5f);
    scene.render.width = 24;
    scene.render.height = 20;
    scene.lights = {defaultKeyLight()};
    Camera camera = cameraOnBox({1, -0.3f, 0.4f});
    camera.fov = 30.0f;
    auto telescoped = prepare(volumeFromGrid(g), scene, camera);
    Light black;
    black.type = LightType::Point;
    black.intensity = 0.0f;
    scene.lights.push_back(black);
    auto per_sample = prepare(volumeFromGrid(g), scene, camera);
    ASSERT_EQ(telescoped->inputs.params.local_light_count, 0);
    ASSERT_EQ(per_sample->inputs.params.local_light_count, 1);
    auto cpu = makeCpuBackend();
    RenderImage a = cpu->march(telescoped->inputs), b = cpu->march(per_sample->inputs);
    float peak = 0.0f;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        peak = std::max(peak, a.pixels[i].direct.x);
        EXPECT_NEAR(a.pixels[i].direct.x, b.pixels[i].direct.x, 1e-5f * (1.0f + b.pixels[i].direct.x)) << i;
        EXPECT_NEAR(a.pixels[i].depth, b.pixels[i].depth, 1e-3f * (1.0f + b.pixels[i].depth)) << i;
        EXPECT_EQ(a.pixels[i].transmittance, b.pixels[i].transmittance) << i;
    }
    EXPECT_GT(peak, 0.1f);
}

}  // namespace
}  // namespace voxlux::test
