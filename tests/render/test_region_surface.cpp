// Surface shading per material (Kniss 2003 Eq. 11 with a 2D transfer function's regions): each
// region's `surface` weight scales the gradient's ramp voxel by voxel, interpolated as the albedo
// is; 1 everywhere is the ramp alone and 0 everywhere is no surface shading, on both backends.
#include <cmath>
#include <optional>

#include "backend/backend_choice.h"
#include "kernel/cpu_kernel_data.h"
#include "render/renderer.h"
#include "test_support.h"
#include "volume/transfer_2d.h"

namespace voxlux::test {
namespace {

// The two halves of twoHalvesGrid(50, 100) as two regions with surface weights `left` and
// `right` (or none).
std::vector<TransferRegion> halvesRegions(std::optional<float> left, std::optional<float> right) {
    TransferRegion a, b;
    a.value = {40.0f, 60.0f};
    b.value = {90.0f, 110.0f};
    a.extinction = b.extinction = 0.3f;
    a.albedo = glm::vec3(0.9f, 0.6f, 0.5f);
    a.surface = left;
    b.surface = right;
    return {a, b};
}

// The halves lit from the upper left and seen from the front right, surface shaded (with a
// specular highlight) when `shaded`.
Scene halvesScene(std::optional<float> left, std::optional<float> right, bool shaded) {
    Scene s;
    s.volume().path = "halves";
    s.render.width = 48;
    s.render.height = 40;
    s.volume().material.transfer_2d = halvesRegions(left, right);
    Camera camera;
    camera.position = glm::vec3(60, 50, 90);
    camera.look_at = glm::vec3(16, 16, 16);
    s.camera = camera;
    if (shaded) {
        SurfaceShading sf;
        sf.gradient_low = 0.0f;
        sf.gradient_high = 0.05f;
        s.effects.surface = sf;
    }
    Light l;
    l.direction = glm::normalize(glm::vec3(0.6f, -1.0f, -0.4f));
    l.intensity = 3.0f;
    s.lights = {l};
    return s;
}

RenderImage render(const Scene& s, KernelBackend& backend) {
    return Renderer(s, volumeFromGrid(twoHalvesGrid(50.0f, 100.0f)), backend).render(std::nullopt, false).image;
}

// Largest |a - b| over the pixels' RGB, relative to a's peak; and that peak.
float relativeDifference(const RenderImage& a, const RenderImage& b, float& peak) {
    peak = 0.0f;
    float worst = 0.0f;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            peak = std::max(peak, a.pixels[i].rgba[c]);
            worst = std::max(worst, std::abs(a.pixels[i].rgba[c] - b.pixels[i].rgba[c]));
        }
    return worst / peak;
}

void expectWeightsOneAndZeroAreTheirLimits(KernelBackend& backend, const char* name) {
    const RenderImage ramp = render(halvesScene(std::nullopt, std::nullopt, true), backend);
    const RenderImage unshaded = render(halvesScene(std::nullopt, std::nullopt, false), backend);
    float peak = 0.0f;
    // The surface shading shows: the two limits differ by far more than the bounds below.
    EXPECT_GT(relativeDifference(ramp, unshaded, peak), 0.05f) << name;
    EXPECT_GT(peak, 0.05f) << name;
    EXPECT_LT(relativeDifference(ramp, render(halvesScene(1.0f, 1.0f, true), backend), peak), 1e-5f) << name << ": weight 1";
    EXPECT_LT(relativeDifference(unshaded, render(halvesScene(0.0f, 0.0f, true), backend), peak), 1e-5f) << name << ": weight 0";
}

TEST(RegionSurface, WeightsOneAndZeroAreTheRampAndNoShadingOnCpu) {
    auto cpu = makeCpuBackend();
    expectWeightsOneAndZeroAreTheirLimits(*cpu, "cpu");
}

TEST(RegionSurface, WeightsOneAndZeroAreTheRampAndNoShadingOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    expectWeightsOneAndZeroAreTheirLimits(*gl, "gl");
}

// Voxel by voxel: 0 in the left half, 1 in the right, and between the two materials' boundary
// voxels the trilinear blend of theirs (the weight is carried out past each material's edge, as
// the albedo is, so the blend never reads the background).
TEST(RegionSurface, TheMarchReadsEachVoxelsOwnWeight) {
    const Scene scene = halvesScene(0.0f, 1.0f, true);
    std::vector<std::string> warnings;
    const LoadedVolume classified = applyTransfer2d(volumeFromGrid(twoHalvesGrid(50.0f, 100.0f)), scene.volume().material.transfer_2d, warnings);
    ASSERT_TRUE(classified.surface);
    auto prepared = prepare(classified, scene, Camera{});
    ASSERT_EQ(prepared->inputs.params.use_surface_grid, 1);
    kernel::CpuKernelData k = bindKernelData(prepared->inputs);
    auto weightAt = [&](glm::vec3 p) {
        const glm::ivec3 brick = glm::ivec3(glm::floor(p / float(VX_BRICK)));
        return k.vx_surface_weight_at(k.vx_single_tap(k.vx_corners_at(k.vx_page_lookup(brick), brick, p)));
    };
    EXPECT_EQ(weightAt({4.0f, 16.0f, 16.0f}), 0.0f);
    EXPECT_EQ(weightAt({27.0f, 16.0f, 16.0f}), 1.0f);
    EXPECT_NEAR(weightAt({15.5f, 16.0f, 16.0f}), 0.5f, 1e-6f);
    EXPECT_NEAR(weightAt({15.25f, 16.0f, 16.0f}), 0.25f, 1e-6f);
    // Without the key, nothing is bound and the march keeps the ramp alone.
    EXPECT_EQ(prepare(applyTransfer2d(volumeFromGrid(twoHalvesGrid(50.0f, 100.0f)), halvesRegions(std::nullopt, std::nullopt), warnings),
                      scene, Camera{})
                  ->inputs.params.use_surface_grid,
              0);
}

}  // namespace
}  // namespace voxlux::test
