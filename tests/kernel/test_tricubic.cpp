// The tricubic filter (render.filter "tricubic"): the kernel's 8 trilinear taps equal the cubic
// B-spline summed over its 4^3 voxels, keep a box's optical depth, stay under the reference's
// majorants, and give the same image on both backends.
#include <algorithm>
#include <cmath>

#include "backend/backend_choice.h"
#include "kernel/cpu_kernel_data.h"
#include "reference/reference_renderer.h"
#include "scene/camera.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// A 20^3 grid of values in [0.05, 0.1], a hundred times denser for x < 8 (brick 0 along x), so
// the filter pulls large values across brick 1's - face.
float noisyValue(int x, int y, int z) {
    const uint32_t h = uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ uint32_t(z) * 83492791u;  // unsigned: no overflow
    const float u = float((h * 2654435761u) >> 8) * 0x1p-24f;
    return (0.05f + 0.05f * u) * (x < 8 ? 100.0f : 1.0f);
}

openvdb::FloatGrid::Ptr noisyGrid(int edge = 20) {
    auto g = openvdb::FloatGrid::create(0.0f);
    auto acc = g->getAccessor();
    for (int z = 0; z < edge; ++z)
        for (int y = 0; y < edge; ++y)
            for (int x = 0; x < edge; ++x) acc.setValue({x, y, z}, noisyValue(x, y, z));
    g->setName("density");
    return g;
}

double bruteForce(glm::dvec3 p) {
    double sum = 0;
    for (int z = int(std::floor(p.z)) - 1; z <= int(std::floor(p.z)) + 2; ++z)
        for (int y = int(std::floor(p.y)) - 1; y <= int(std::floor(p.y)) + 2; ++y)
            for (int x = int(std::floor(p.x)) - 1; x <= int(std::floor(p.x)) + 2; ++x) {
                const bool inside = x >= 0 && y >= 0 && z >= 0 && x < 20 && y < 20 && z < 20;
                if (inside) sum += cubicBSpline(p.x - x) * cubicBSpline(p.y - y) * cubicBSpline(p.z - z) * noisyValue(x, y, z);
            }
    return sum;
}

Scene tricubicScene() {
    Scene s;
    s.render.width = 24;
    s.render.height = 24;
    s.render.filter = Filter::Tricubic;
    s.effects.shadows = ShadowMethod::None;
    return s;
}

// Points spread through [0, 16)^3 (the grid with its - border, away from its + border, where
// the march stops at the last stored brick).
glm::vec3 samplePoint(int i) {
    const auto frac = [](double v) { return float(v - std::floor(v)); };
    return 16.0f * glm::vec3(frac(i * 0.7548776662), frac(i * 0.5698402910), frac(i * 0.3141592653 + 0.5));
}

TEST(Tricubic, EqualsTheBSplineSumOverItsVoxels) {
    auto prepared = prepare(volumeFromGrid(noisyGrid()), tricubicScene(), cameraAlong(glm::vec3(10), {0, 0, -1}, 200, 30));
    kernel::CpuKernelData k = bindKernelData(prepared->inputs);
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 p = samplePoint(i);
        worst = std::max(worst, std::abs(double(k.vx_density_index(p)) - bruteForce(p)));
    }
    EXPECT_LT(worst, 1e-5);  // float rounding of values up to 10
    // Trilinear reads differ from it: the test sees the filter, not the data.
    k.P.voxel_filter = VX_FILTER_TRILINEAR;
    const glm::vec3 off_grid(7.3f, 4.6f, 9.2f);
    EXPECT_GT(std::abs(double(k.vx_density_index(off_grid)) - bruteForce(off_grid)), 1e-3);
}

// Reference: every extinction a sample can read lies between its slot's minorant and majorant,
// although the B-spline reads neighbouring bricks (the slot's own range would be exceeded at brick
// 0's + face). The grid is 40 voxels wide, so that the bricks whose blocks and neighbours hold no
// background have minorants above 0.
TEST(Tricubic, ExtinctionBoundsBoundEverySample) {
    auto prepared = prepare(volumeFromGrid(noisyGrid(40)), tricubicScene(), cameraAlong(glm::vec3(10), {0, 0, -1}, 200, 30));
    const ExtinctionBounds bounds = brickExtinctionBounds(prepared->inputs);
    kernel::CpuKernelData k = bindKernelData(prepared->inputs);
    float worst_ratio = 0, own_range_ratio = 0, worst_below_minorant = 0;
    for (int i = 0; i < 4000; ++i) {
        const glm::vec3 p = 2.0f * samplePoint(i);  // over [0, 32)^3
        const glm::ivec3 b(glm::floor(p / float(VX_BRICK)));
        const int slot = k.vx_page_lookup(b);
        ASSERT_NE(slot, VX_PAGE_EMPTY);
        const float sigma = k.vx_extinction(k.vx_taps_at(slot, b, p));
        worst_ratio = std::max(worst_ratio, sigma / bounds.majorant[size_t(slot)]);
        worst_below_minorant = std::max(worst_below_minorant, bounds.minorant[size_t(slot)] - sigma);
        own_range_ratio = std::max(own_range_ratio, sigma / k.vx_value_extinction(prepared->atlas.density_range[size_t(slot)].y));
    }
    EXPECT_LE(worst_ratio, 1.0f);
    EXPECT_GT(own_range_ratio, 2.0f);
    EXPECT_LE(worst_below_minorant, 0.0f);
    EXPECT_GT(*std::max_element(bounds.minorant.begin(), bounds.minorant.end()), 0.0f);
}

// A colour grid wider than the density: the B-spline reproduces a constant colour exactly, also
// next to a brick the classify stage would drop for having no density (its colour is read, not 0).
TEST(Tricubic, ReadsTheColourOfBricksWithoutDensity) {
    const glm::vec3 tint(0.2f, 0.5f, 0.8f);
    auto color = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    color->setName("Cd");
    color->denseFill(openvdb::CoordBBox({0, 0, 0}, {23, 23, 23}), openvdb::Vec3s(tint.x, tint.y, tint.z));
    auto prepared = prepare(volumeFromGrid(boxGrid({8, 8, 8}, {15, 15, 15}, 1.0f), {}, color), tricubicScene(),
                            cameraAlong(glm::vec3(12), {0, 0, -1}, 200, 30));
    kernel::CpuKernelData k = bindKernelData(prepared->inputs);
    ASSERT_NE(k.vx_page_lookup(glm::ivec3(0, 1, 1)), VX_PAGE_EMPTY) << "a brick of colour only, next to the density";
    for (float x : {8.05f, 8.5f, 12.0f, 15.5f}) {
        const glm::vec3 p(x, 12.3f, 11.7f);
        const glm::ivec3 b(glm::floor(p / float(VX_BRICK)));
        const glm::vec3 albedo = k.vx_albedo(k.vx_taps_at(k.vx_page_lookup(b), b, p));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(albedo[c], k.P.albedo[c] * tint[c], 1e-5) << "x " << x << " channel " << c;
    }
}

// The B-spline is a partition of unity, so it keeps a box's optical depth: a ray across the box
// along x meets sigma * 63 voxels, as with trilinear. The box ends at voxel 62 so that its fade
// stays inside stored bricks. The march and the reference's residual ratio tracking agree with it;
// the box's inner bricks are uniform, so there the tracking is exact.
TEST(Tricubic, KeepsTheOpticalDepthOfABox) {
    const float sigma = 0.02f, voxel = 0.5f;
    auto grid = boxGrid({0, 0, 0}, {62, 62, 62}, sigma, voxel);
    const glm::vec3 centre(31.0f * voxel);
    Scene scene = tricubicScene();
    scene.render.width = scene.render.height = 9;
    scene.render.step = 0.25f;
    auto prepared = prepare(volumeFromGrid(grid), scene, cameraAlong(centre, {1, 0, 0}, 200, 1));
    const double expected = std::exp(-double(sigma) * 63 * voxel);
    EXPECT_NEAR(makeCpuBackend()->march(prepared->inputs).pixels[4 * 9 + 4].transmittance, expected, 1e-4);

    const ExtinctionBounds bounds = brickExtinctionBounds(prepared->inputs);
    EXPECT_FLOAT_EQ(*std::max_element(bounds.minorant.begin(), bounds.minorant.end()), sigma);
    double sum = 0;
    const int n = 4000;
    for (int s = 0; s < n; ++s) {
        ReferenceRng rng(1, 0, uint32_t(s));
        sum += ratioTrackedTransmittance(prepared->inputs, bounds, centre - glm::vec3(100, 0, 0), {1, 0, 0}, 200, rng);
    }
    EXPECT_NEAR(sum / n, expected, 0.03);  // about 4 standard errors of the binary estimator here
}

// Both backends run the same taps: the noisy grid with ray-marched shadows, pixel by pixel.
TEST(Tricubic, CpuAndGlAgreeOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = tricubicScene();
    scene.effects.shadows = ShadowMethod::Raymarch;
    Light key;
    key.type = LightType::Directional;
    key.direction = glm::normalize(glm::vec3(-1, -2, -1));
    key.intensity = 3;
    scene.lights.push_back(key);
    auto prepared = prepare(volumeFromGrid(noisyGrid()), scene, cameraAlong(glm::vec3(10), {0.3f, -0.2f, -1}, 200, 40));
    const RenderImage cpu = makeCpuBackend()->march(prepared->inputs), gpu = gl->march(prepared->inputs);
    double worst = 0, lit = 0;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) {
        lit = std::max(lit, double(cpu.pixels[i].rgba.x));
        for (int c = 0; c < 4; ++c) worst = std::max(worst, double(std::abs(cpu.pixels[i].rgba[c] - gpu.pixels[i].rgba[c])));
    }
    EXPECT_GT(lit, 0.05);
    EXPECT_LT(worst, 1e-3);
}

}  // namespace
}  // namespace voxlux::test
