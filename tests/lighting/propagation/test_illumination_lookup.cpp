// How the march reads the illumination volume (effects.propagation.filter): the cubic B-spline
// equals its sum over the 4x4x4 cells around a point, edges repeated; and on a smooth, dense
// medium lit by a light grid coarser than the pixels it leaves no bands at the light cells, where
// the trilinear read does.
#include <algorithm>
#include <cmath>

#include "backend/backend_choice.h"
#include "kernel/cpu_kernel.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

float hashed(int i) {
    const uint32_t h = uint32_t(i) * 2654435761u;
    return float(h >> 8) * 0x1p-24f;
}

TEST(IlluminationLookup, SplineEqualsTheBSplineSumOverItsCells) {
    const glm::ivec3 dims(7, 5, 6);
    std::vector<float> values(size_t(3 * dims.x * dims.y * dims.z));
    for (size_t i = 0; i < values.size(); ++i) values[i] = hashed(int(i));
    kernel::CpuKernel k;
    k.illum = values;
    k.P.illum_dims = dims;
    k.P.world_to_illum = glm::mat4(1.0f);
    k.P.light_filter = VX_FILTER_TRICUBIC;
    const auto value = [&](glm::ivec3 c, int ch) {
        c = glm::clamp(c, glm::ivec3(0), dims - 1);
        return double(values[size_t(3 * ((c.z * dims.y + c.y) * dims.x + c.x) + ch)]);
    };
    double worst = 0, worst_trilinear = 0;
    for (int n = 0; n < 500; ++n) {
        // Points over the grid and half a cell past its faces (cell centres at i + 0.5).
        const glm::vec3 q = glm::vec3(hashed(3 * n + 1), hashed(3 * n + 2), hashed(3 * n + 3)) * glm::vec3(dims + 1) - 0.5f;
        const glm::vec3 g = q - 0.5f;
        const glm::ivec3 first(glm::floor(g));
        glm::dvec3 expected(0.0);
        for (int z = first.z - 1; z <= first.z + 2; ++z)
            for (int y = first.y - 1; y <= first.y + 2; ++y)
                for (int x = first.x - 1; x <= first.x + 2; ++x) {
                    const double w = cubicBSpline(g.x - x) * cubicBSpline(g.y - y) * cubicBSpline(g.z - z);
                    for (int ch = 0; ch < 3; ++ch) expected[ch] += w * value({x, y, z}, ch);
                }
        k.P.light_filter = VX_FILTER_TRICUBIC;
        worst = std::max(worst, glm::length(glm::dvec3(k.vx_illum_direct(q)) - expected));
        k.P.light_filter = VX_FILTER_TRILINEAR;
        worst_trilinear = std::max(worst_trilinear, glm::length(glm::dvec3(k.vx_illum_direct(q)) - expected));
    }
    EXPECT_LT(worst, 1e-5);
    EXPECT_GT(worst_trilinear, 1e-2) << "the test sees the filter";
}

// Blended spheres with no noise (a metaball field smoothstepped to a dense core), 64 voxels
// across the unit cube: about 1.6 extinction per voxel at density_scale 102.
openvdb::FloatGrid::Ptr smoothSpheres() {
    struct Sphere {
        glm::vec3 centre;
        float radius;
    };
    const Sphere spheres[] = {{{0, 0, 0}, 0.28f}, {{0.22f, 0.08f, 0.05f}, 0.2f}, {{-0.2f, 0.05f, -0.08f}, 0.22f}, {{0.05f, 0.2f, 0.1f}, 0.18f}};
    const int n = 64;
    const float voxel = 1.0f / n;
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    auto acc = grid->getAccessor();
    for (int i = -n / 2; i <= n / 2; ++i)
        for (int j = -n / 2; j <= n / 2; ++j)
            for (int k = -n / 2; k <= n / 2; ++k) {
                const glm::vec3 p = glm::vec3(i, j, k) * voxel;
                float field = 0;
                for (const Sphere& s : spheres) field += std::exp(-2.0f * glm::dot(p - s.centre, p - s.centre) / (s.radius * s.radius));
                const float t = std::clamp((field - 0.25f) / 0.35f, 0.0f, 1.0f);
                if (t > 0) acc.setValue({i, j, k}, t * t * (3 - 2 * t));
            }
    return grid;
}

std::vector<double> luminanceOf(const RenderImage& img) {
    std::vector<double> y;
    for (const auto& p : img.pixels) y.push_back(0.2126 * p.rgba.x + 0.7152 * p.rgba.y + 0.0722 * p.rgba.z);
    return y;
}

// The second differences of neighbouring pixels, along x and y, over the inside of the image
// (every pixel within 3 of it at least 5% of the peak), relative to the mean there: a band or a
// seam is a kink, a spike in the second difference. For two independent renders a and b of one
// truth, the mean of d2(a) d2(b) estimates the truth's squared second difference, free of their
// noise; `se` is its standard error.
struct Kinks {
    double fast_rms = 0;         // of the fast image
    double truth_squared = 0;    // mean d2(a) d2(b)
    double se = 0;
};

Kinks kinks(const std::vector<double>& fast, const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
    double peak = 0;
    for (size_t i = 0; i < a.size(); ++i) peak = std::max(peak, 0.5 * (a[i] + b[i]));
    double f2 = 0, ab = 0, ab2 = 0, mean = 0;
    int n = 0;
    for (int y = 3; y < h - 3; ++y)
        for (int x = 3; x < w - 3; ++x) {
            bool inside = true;
            for (int dy = -3; dy <= 3; ++dy)
                for (int dx = -3; dx <= 3; ++dx) {
                    const size_t j = size_t((y + dy) * w + x + dx);
                    inside = inside && 0.5 * (a[j] + b[j]) > 0.05 * peak;
                }
            if (!inside) continue;
            const size_t i = size_t(y * w + x);
            for (size_t s : {size_t(1), size_t(w)}) {
                const auto d2 = [&](const std::vector<double>& v) { return v[i - s] - 2 * v[i] + v[i + s]; };
                f2 += d2(fast) * d2(fast);
                ab += d2(a) * d2(b);
                ab2 += d2(a) * d2(b) * d2(a) * d2(b);
                ++n;
            }
            mean += a[i] + b[i];
        }
    mean /= double(n);  // n counts two differences per pixel, mean two renders
    Kinks k;
    k.fast_rms = std::sqrt(f2 / n) / mean;
    k.truth_squared = ab / n / (mean * mean);
    k.se = std::sqrt(std::max(ab2 / n - (ab / n) * (ab / n), 0.0) / n) / (mean * mean);
    return k;
}

// The scene: the sun from above and the side, a light grid of 16 cells (each about 6
// pixels), the preview's other settings. The trilinear read kinks at every light cell; the
// spline's second differences stay within what the reference shows (its estimate plus 3 standard
// errors), and the trilinear ones exceed it, so the metric sees the bands.
TEST(IlluminationLookup, SmoothDenseMediumShowsNoBandsAtTheLightCells) {
    Scene s;
    s.render.width = s.render.height = 96;
    s.material.density_scale = 102.4f;
    s.material.albedo = glm::vec3(0.94f);
    Light sun;
    sun.direction = glm::normalize(glm::vec3(-0.5f, -0.85f, 0.0f));
    sun.intensity = 12.0f;
    Light sky;
    sky.type = LightType::Ambient;
    sky.color = glm::vec3(0.5f, 0.6f, 0.8f);
    sky.intensity = 0.3f;
    s.lights = {sun, sky};
    s.camera = cameraAlong(glm::vec3(0.0f), {0, 0, -1}, 2.4f, 30.0f);
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.light_resolution = 16;
    s.effects.indirect = Indirect{};
    auto cpu = makeCpuBackend();
    Renderer renderer(s, volumeFromGrid(smoothSpheres()), *cpu);
    const auto render = [&](const std::function<void(Scene&)>& edit) {
        Scene e = s;
        edit(e);
        renderer.setScene(e);
        return luminanceOf(renderer.render(std::nullopt, false).image);
    };
    const auto spline = render([](Scene&) {});
    const auto trilinear = render([](Scene& e) { e.effects.propagation.filter = Filter::Trilinear; });
    const auto reference = [&](int seed) {
        return render([seed](Scene& e) {
            e.render.method = RenderMethod::Reference;
            e.render.reference.spp = 1024;
            e.render.reference.seed = seed;
        });
    };
    const auto a = reference(1), b = reference(2);
    const Kinks with_spline = kinks(spline, a, b, 96, 96), with_trilinear = kinks(trilinear, a, b, 96, 96);
    const double bound = std::sqrt(std::max(with_spline.truth_squared, 0.0) + 3 * with_spline.se);
    std::printf("rms second difference / mean: spline %.5f, trilinear %.5f, reference %.5f (SE of its square %.5f; bound %.5f)\n", with_spline.fast_rms,
                with_trilinear.fast_rms, std::sqrt(std::max(with_spline.truth_squared, 0.0)), with_spline.se, bound);
    EXPECT_LE(with_spline.fast_rms, bound);
    EXPECT_GT(with_trilinear.fast_rms, bound);
}

}  // namespace
}  // namespace voxlux::test
