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

// The brute-force B-spline at grid point q of a block of `dims` cells (centres at i + 0.5), the
// edge cells repeated past its faces; `value(c, ch)` reads cell c.
glm::dvec3 bruteForceSpline(glm::vec3 q, glm::ivec3 dims, const std::function<double(glm::ivec3, int)>& value) {
    const glm::vec3 g = q - 0.5f;
    const glm::ivec3 first(glm::floor(g));
    glm::dvec3 sum(0.0);
    for (int z = first.z - 1; z <= first.z + 2; ++z)
        for (int y = first.y - 1; y <= first.y + 2; ++y)
            for (int x = first.x - 1; x <= first.x + 2; ++x) {
                const double w = cubicBSpline(g.x - x) * cubicBSpline(g.y - y) * cubicBSpline(g.z - z);
                const glm::ivec3 c = glm::clamp(glm::ivec3(x, y, z), glm::ivec3(0), dims - 1);
                for (int ch = 0; ch < 3; ++ch) sum[ch] += w * value(c, ch);
            }
    return sum;
}

// Both blocks: the direct light, and the indirect light on a grid chroma-subsampled by 2, after
// the direct block in the same array.
TEST(IlluminationLookup, SplineEqualsTheBSplineSumOverItsCells) {
    const glm::ivec3 dims(7, 5, 6), coarse(4, 3, 3);
    const int indirect_offset = 3 * dims.x * dims.y * dims.z;
    std::vector<float> values(size_t(indirect_offset + 3 * coarse.x * coarse.y * coarse.z));
    for (size_t i = 0; i < values.size(); ++i) values[i] = hashed(int(i));
    kernel::CpuKernel k;
    k.illum = values;
    kernel::VxPropagationMarch& b = k.L.propagation;
    b.illum_dims = dims;
    b.world_to_illum = glm::mat4(1.0f);
    b.indirect_weight = 1.0f;
    b.chroma_factor = 2;
    b.chroma_dims = coarse;
    b.indirect_offset = indirect_offset;
    const auto cellOf = [&](glm::ivec3 d, int offset) {
        return [&values, d, offset](glm::ivec3 c, int ch) { return double(values[size_t(offset + 3 * ((c.z * d.y + c.y) * d.x + c.x) + ch)]); };
    };
    double worst = 0, worst_trilinear = 0;
    for (int n = 0; n < 500; ++n) {
        // Points over the grid and up to a cell past its faces (cell centres at i + 0.5).
        const glm::vec3 q = glm::vec3(hashed(3 * n + 1), hashed(3 * n + 2), hashed(3 * n + 3)) * glm::vec3(dims + 2) - 1.0f;
        const glm::dvec3 direct = bruteForceSpline(q, dims, cellOf(dims, 0));
        const glm::dvec3 indirect = bruteForceSpline(q / 2.0f, coarse, cellOf(coarse, indirect_offset));
        // The volume's sample at q: the world is its cell space here.
        const auto at = k.vx_propagation_sample(q);
        b.light_filter = VX_FILTER_TRICUBIC;
        worst = std::max({worst, glm::length(glm::dvec3(k.vx_propagation_direct(at, glm::vec3(1.0f), glm::vec3(1.0f), 0)) - direct),
                          glm::length(glm::dvec3(k.vx_propagation_indirect(at, 0)) - indirect)});
        b.light_filter = VX_FILTER_TRILINEAR;
        worst_trilinear = std::max(worst_trilinear, glm::length(glm::dvec3(k.vx_propagation_direct(at, glm::vec3(1.0f), glm::vec3(1.0f), 0)) - direct));
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
    for (const auto& p : img.pixels) y.push_back(luminance(glm::vec3(p.rgba)));
    return y;
}

// The second differences of neighbouring pixels, along x and y, over the inside of the image
// (every pixel within 3 of it at least 5% of the peak), relative to the mean there: a band or a
// seam is a kink, a spike in the second difference. For two independent renders a and b of one
// truth, the mean of d2(a) d2(b) estimates the truth's squared second difference, free of their
// noise. Neighbouring differences share pixels, so its standard error `se` comes from 8x8 tiles,
// which share few: the spread of the tiles' sums about their share of the mean.
struct Kinks {
    double fast_rms = 0;         // of the fast image
    double truth_squared = 0;    // mean d2(a) d2(b)
    double se = 0;
};

Kinks kinks(const std::vector<double>& fast, const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
    double peak = 0;
    for (size_t i = 0; i < a.size(); ++i) peak = std::max(peak, 0.5 * (a[i] + b[i]));
    const int tiles_x = (w + 7) / 8;
    std::vector<double> tile_ab(size_t(tiles_x * ((h + 7) / 8)), 0.0), tile_n(tile_ab.size(), 0.0);
    double f2 = 0, ab = 0, mean = 0;
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
            const size_t i = size_t(y * w + x), tile = size_t(y / 8 * tiles_x + x / 8);
            for (size_t s : {size_t(1), size_t(w)}) {
                const auto d2 = [&](const std::vector<double>& v) { return v[i - s] - 2 * v[i] + v[i + s]; };
                f2 += d2(fast) * d2(fast);
                ab += d2(a) * d2(b);
                tile_ab[tile] += d2(a) * d2(b);
                tile_n[tile] += 1;
                ++n;
            }
            mean += a[i] + b[i];
        }
    mean /= double(n);  // n counts two differences per pixel, mean two renders
    double spread = 0;
    for (size_t t = 0; t < tile_ab.size(); ++t) spread += std::pow(tile_ab[t] - tile_n[t] * ab / n, 2);
    Kinks k;
    k.fast_rms = std::sqrt(f2 / n) / mean;
    k.truth_squared = ab / n / (mean * mean);
    k.se = std::sqrt(spread) / n / (mean * mean);
    return k;
}

// A smooth cloud as an artist makes one: the sun from above and the side, a light grid of 16
// cells (each about 6 pixels), the preview's other settings. The spline's second differences stay
// within what the reference shows (its estimate plus 3 standard errors). The trilinear read kinks
// at every light cell: its second differences are several times the spline's and half as much
// again as the truth's estimate, so the metric sees the bands (at 1024 spp the reference's noise
// leaves its 3-SE bound just above them).
TEST(IlluminationLookup, SmoothDenseMediumShowsNoBandsAtTheLightCells) {
    Scene s;
    s.render.width = s.render.height = 96;
    s.volume().material.density_scale = 102.4f;
    s.volume().material.albedo = glm::vec3(0.94f);
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
    EXPECT_GT(with_trilinear.fast_rms, 3 * with_spline.fast_rms);
    EXPECT_GT(with_trilinear.fast_rms, 1.5 * std::sqrt(std::max(with_spline.truth_squared, 0.0)));
}

}  // namespace
}  // namespace voxlux::test
