// The Monte Carlo reference (render.method "reference") against analytic results and the march:
// ratio-tracked transmittance, the white furnace, single scattering, single-scattered ambient
// light, emission, the variance against the previous estimators, energy, determinism, and the
// scene keys.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "backend/backend_choice.h"
#include "kernel/cpu_kernel_data.h"
#include "core/error.h"
#include "reference/reference_renderer.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kN = 64;          // box edge in voxels
constexpr double kVoxel = 0.5;

Scene referenceScene(int size, int spp) {
    Scene s;
    s.render.width = size;
    s.render.height = size;
    s.render.method = RenderMethod::Reference;
    s.render.reference.spp = spp;
    return s;
}

Light ambientLight(float radiance) {
    Light l;
    l.type = LightType::Ambient;
    l.intensity = radiance;
    return l;
}

double meanLuminance(const RenderImage& img) {
    double sum = 0.0;
    for (const auto& p : img.pixels) sum += luminance(glm::vec3(p.rgba));
    return sum / double(img.pixels.size());
}

// Residual ratio tracking through a homogeneous box along the axes: the mean of independent
// estimates matches exp(-sigma * d) within 4 standard errors computed from the estimates themselves. Beyond
// the last voxel centre trilinear reconstruction ramps to zero over one voxel, so an axis ray sees
// kN voxels of full density (as the march's transmittance test).
TEST(Reference, RatioTrackedTransmittanceOfAHomogeneousBox) {
    const double d = kN * kVoxel;
    const glm::vec3 centre(float((kN - 1) * 0.5 * kVoxel));
    for (double optical_depth : {0.1, 1.0, 4.0}) {
        const float sigma = float(optical_depth / d);
        auto prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {kN - 1, kN - 1, kN - 1}, sigma, kVoxel)),
                                referenceScene(1, 1), cameraAlong(centre, {1, 0, 0}, 200.0f, 1.0f));
        const ExtinctionBounds bounds = brickExtinctionBounds(prepared->inputs);
        const glm::vec3 axes[] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
        for (uint32_t a = 0; a < 3; ++a) {
            const glm::vec3 start = centre - axes[a] * 100.0f;
            constexpr int kSamples = 200000;
            double sum = 0.0, sum2 = 0.0;
            for (int i = 0; i < kSamples; ++i) {
                ReferenceRng rng(7, a, uint32_t(i));
                const double T = ratioTrackedTransmittance(prepared->inputs, bounds, start, axes[a], 200.0f, rng);
                sum += T;
                sum2 += T * T;
            }
            const double mean = sum / kSamples;
            const double se = std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean) / (kSamples - 1));
            const double expected = std::exp(-optical_depth);
            std::printf("ratio tracking, sigma*d %.1f: T %.5f +- %.5f (exp %.5f)\n", optical_depth, mean, se, expected);
            EXPECT_NEAR(mean, expected, 4.0 * se + 1e-6) << "sigma*d " << optical_depth;
        }
    }
}

// A box of voxel 1 seen face-on by a narrow camera: every pixel's ray enters the front face.
struct Furnace {
    std::unique_ptr<Prepared> prepared;
    RenderImage image;
};

Furnace whiteFurnace(float optical_depth, int size, int spp) {
    constexpr int kEdge = 32;
    Scene scene = referenceScene(size, spp);
    scene.volume().material.albedo = glm::vec3(1.0f);
    scene.render.reference.max_bounces = 1000;  // paths in a thick albedo-1 box scatter long
    scene.lights = {ambientLight(1.0f)};
    const glm::vec3 centre((kEdge - 1) * 0.5f);
    Furnace f;
    f.prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {kEdge - 1, kEdge - 1, kEdge - 1}, optical_depth / kEdge)),
                         scene, cameraAlong(centre, {0, 0, -1}, 100.0f, 10.0f));
    f.image = renderReference(f.prepared->inputs, scene.render.reference);
    return f;
}

// A non-absorbing medium under uniform light L returns L wherever a ray meets it: every path
// that enters leaves again carrying L. Premultiplied, the beauty is alpha * L.
TEST(Reference, WhiteFurnace) {
    const Furnace thick = whiteFurnace(8.0f, 4, 1024);
    double rgb = 0.0, alpha = 0.0;
    for (const auto& p : thick.image.pixels) {
        rgb += luminance(glm::vec3(p.rgba));
        alpha += p.rgba.w;
    }
    std::printf("white furnace, thick box: unpremultiplied %.5f, alpha %.5f\n", rgb / alpha, alpha / 16.0);
    EXPECT_NEAR(rgb / alpha, 1.0, 0.01);
    EXPECT_GT(alpha / 16.0, 0.999);

    const Furnace thin = whiteFurnace(0.9f, 8, 4096);
    rgb = alpha = 0.0;
    for (const auto& p : thin.image.pixels) {
        rgb += luminance(glm::vec3(p.rgba));
        alpha += p.rgba.w;
    }
    rgb /= 64.0;
    alpha /= 64.0;
    std::printf("white furnace, thin box: premultiplied %.5f, alpha %.5f (1 - e^-0.9 = %.5f)\n", rgb, alpha,
                1.0 - std::exp(-0.9));
    EXPECT_LT(alpha, 0.7);
    EXPECT_NEAR(rgb, alpha, 0.01 * alpha);
}

// A small noisy ball under one directional light.
struct Ball {
    Scene scene;
    LoadedVolume volume;
};

Ball ball(const std::string& folder) {
    Ball b;
    b.scene = referenceScene(12, 1024);
    b.scene.volume().material.density_scale = 1.5f;
    b.scene.volume().material.anisotropy = 0.3f;
    Light key;
    key.direction = glm::vec3(-1.0f, -0.5f, -0.7f);
    key.intensity = 3.0f;
    b.scene.lights = {key};
    b.scene.camera = cameraAlong(glm::vec3(0.0f), {0.2f, -0.1f, -1.0f}, 8.0f, 32.0f);
    b.volume = loadVolume(writeBall(tempDir(folder)), b.scene.volume());
    return b;
}

// With one bounce the reference estimates the march's single-scattering integral: per pixel
// within 4 of the reference's own standard deviations (variance AOV) for 95% of pixels, and the
// image mean within 1%.
TEST(Reference, SingleScatteringMatchesTheMarch) {
    Ball b = ball("reference_single");
    b.scene.render.reference.max_bounces = 1;
    b.scene.effects.shadows = ShadowMethod::Raymarch;
    b.scene.render.step = 0.1f;
    b.scene.render.shadow_step = 0.1f;
    b.scene.render.transmittance_cutoff = 1e-6f;
    auto prepared = prepare(b.volume, b.scene, *b.scene.camera);
    const RenderImage ref = renderReference(prepared->inputs, b.scene.render.reference);
    const RenderImage march = makeCpuBackend()->march(prepared->inputs);
    int within = 0, lit = 0;
    for (size_t i = 0; i < ref.pixels.size(); ++i) {
        const double r = luminance(glm::vec3(ref.pixels[i].rgba)), m = luminance(glm::vec3(march.pixels[i].rgba));
        if (m > 0.0) ++lit;
        within += std::abs(r - m) <= 4.0 * std::sqrt(double(ref.pixels[i].variance)) + 1e-6;
    }
    const double mr = meanLuminance(ref), mm = meanLuminance(march);
    std::printf("single scattering: %d of %zu pixels within 4 sigma (%d lit); image mean %.5f vs march %.5f (%.2f%%)\n",
                within, ref.pixels.size(), lit, mr, mm, 100.0 * (mr / mm - 1.0));
    EXPECT_GT(lit, int(ref.pixels.size() / 2));
    EXPECT_GE(within, int(0.95 * ref.pixels.size()));
    EXPECT_NEAR(mr, mm, 0.01 * mm);
}

// The ball glowing with its own density (a constant source from the density grid), unlit. With
// albedo 0 nothing scatters: the reference's emission is the march's emission integral, per pixel
// within 4 of its standard deviations and the image mean within 1%. With albedo 0.8 the glow also
// lights the medium itself (scattered emission, in the indirect AOV), which the march gets only
// from propagated indirect light (off here; tests/lighting/propagation/test_emitted_light.cpp
// compares it): the emission AOVs still agree, and the beauty is brighter than the march's.
TEST(Reference, EmissionMatchesTheMarchAndAlsoLightsTheMedium) {
    Ball b = ball("reference_emission");
    b.scene.lights.clear();
    b.scene.render.reference.spp = 256;
    b.scene.render.step = 0.1f;
    b.scene.render.transmittance_cutoff = 1e-6f;
    EmissionSource glow;
    glow.grid.name = "density";
    glow.color = glm::vec3(1.0f, 0.5f, 0.2f);
    glow.intensity = 2.0f;
    b.scene.volume().emission = {glow};
    b.volume = loadVolume(b.volume.file, b.scene.volume());
    for (float albedo : {0.0f, 0.8f}) {
        b.scene.volume().material.albedo = glm::vec3(albedo);
        auto prepared = prepare(b.volume, b.scene, *b.scene.camera);
        const RenderImage ref = renderReference(prepared->inputs, b.scene.render.reference);
        const RenderImage march = makeCpuBackend()->march(prepared->inputs);
        int within = 0, glowing = 0;
        double sr = 0.0, sm = 0.0, indirect = 0.0;
        for (size_t i = 0; i < ref.pixels.size(); ++i) {
            const double r = luminance(ref.pixels[i].emission), m = luminance(march.pixels[i].emission);
            glowing += m > 0.0;
            sr += r, sm += m, indirect += luminance(ref.pixels[i].indirect);
            within += std::abs(r - m) <= 4.0 * std::sqrt(double(ref.pixels[i].variance)) + 1e-6;
        }
        std::printf("emission, albedo %.1f: %d of %zu pixels within 4 sigma (%d glowing); emission mean %.5f vs march "
                    "%.5f (%.2f%%); scattered emission %.5f\n",
                    albedo, within, ref.pixels.size(), glowing, sr / ref.pixels.size(), sm / ref.pixels.size(),
                    100.0 * (sr / sm - 1.0), indirect / ref.pixels.size());
        EXPECT_GT(glowing, int(ref.pixels.size() / 2));
        EXPECT_GE(within, int(0.95 * ref.pixels.size()));
        EXPECT_NEAR(sr, sm, 0.01 * sm);
        if (albedo == 0.0f) EXPECT_EQ(indirect, 0.0);
        else EXPECT_GT(indirect, 0.05 * sm);
    }
}

// Single scattering of a uniform ambient radiance L in a homogeneous box (extinction sigma,
// albedo 1, isotropic), along the ray through its centre parallel to an edge: L times the integral
// over the chord of sigma e^(-sigma t) g(x(t)), g(x) being the mean over directions of the
// transmittance out of the box from x. The reference's last flight (max_bounces 1) brings the
// ambient light as that transmittance, ratio-tracked. Brute-force quadrature (200 points along the
// ray, 300 x 300 directions) against 16384 spp, within 1%. Trilinear reconstruction ramps the
// density to 0 over the voxel beyond the last voxel centre: to first order, a sharp box half a
// voxel wider on each side.
TEST(Reference, SingleScatteredAmbientLightMatchesAQuadrature) {
    constexpr int kEdge = 64;
    constexpr double kSigma = 2.0 / kEdge;  // an optical half-width of 1
    Scene scene = referenceScene(1, 16384);
    scene.volume().material.albedo = glm::vec3(1.0f);
    scene.render.reference.max_bounces = 1;
    scene.lights = {ambientLight(1.0f)};
    const glm::vec3 centre((kEdge - 1) * 0.5f);
    auto prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {kEdge - 1, kEdge - 1, kEdge - 1}, float(kSigma))), scene,
                            cameraAlong(centre, {1, 0, 0}, 100.0f, 1.0f));
    const double measured = luminance(glm::vec3(renderReference(prepared->inputs, scene.render.reference).pixels[0].rgba));

    const double lo = -0.5, hi = kEdge - 0.5, c = centre.x;
    constexpr int kSteps = 200, kDirections = 300;
    double sum = 0.0;
    for (int i = 0; i < kSteps; ++i) {
        const double t = (i + 0.5) * (hi - lo) / kSteps;
        const double x[3] = {lo + t, c, c};
        double g = 0.0;
        for (int j = 0; j < kDirections; ++j) {
            const double mu = -1.0 + (j + 0.5) * 2.0 / kDirections, sine = std::sqrt(1.0 - mu * mu);
            for (int k = 0; k < kDirections; ++k) {
                const double phi = (k + 0.5) * 2.0 * M_PI / kDirections;
                const double w[3] = {sine * std::cos(phi), sine * std::sin(phi), mu};
                double s = INFINITY;
                for (int a = 0; a < 3; ++a)
                    if (w[a] != 0.0) s = std::min(s, ((w[a] > 0.0 ? hi : lo) - x[a]) / w[a]);
                g += std::exp(-kSigma * s);
            }
        }
        sum += kSigma * std::exp(-kSigma * t) * g / (double(kDirections) * kDirections) * (hi - lo) / kSteps;
    }
    std::printf("single-scattered ambient light through a box: %.5f, quadrature %.5f (%+.2f%%)\n", measured, sum,
                100.0 * (measured / sum - 1.0));
    EXPECT_NEAR(measured, sum, 0.01 * sum);
}

// The variance at equal samples per pixel against the estimators these replaced (delta tracking
// from the camera, plain ratio tracking, binary escapes, independent random numbers), whose RMSE
// here this same test measured at commit 354cdc6. Both are unbiased, so each is measured against
// a 4096-spp render of itself: the ball at 16x16 under its key light and a sky, albedo 0.9, RMSE
// of the luminance at 16 spp over 8 seeds. It must be at most the previous RMSE over
// sqrt(factor). Measured: variance / 3.9 in single scattering, / 2.1 in multiple scattering (up to
// 16 bounces). docs/accuracy.md gives the seconds on the study scenes and against Cycles.
void expectVarianceFallsBy(const char* what, int max_bounces, double previous_rmse, double factor) {
    Ball b = ball(std::string("variance_") + what);
    b.scene.render.width = b.scene.render.height = 16;
    b.scene.render.reference.max_bounces = max_bounces;
    b.scene.volume().material.albedo = glm::vec3(0.9f);
    b.scene.lights.push_back(ambientLight(0.5f));
    auto prepared = prepare(b.volume, b.scene, *b.scene.camera);
    ReferenceSettings rs = b.scene.render.reference;
    rs.spp = 4096;
    rs.seed = 1000;
    const RenderImage truth = renderReference(prepared->inputs, rs);
    double sum = 0.0;
    size_t n = 0;
    for (int seed = 1; seed <= 8; ++seed) {
        rs.spp = 16;
        rs.seed = seed;
        const RenderImage img = renderReference(prepared->inputs, rs);
        for (size_t i = 0; i < img.pixels.size(); ++i, ++n) {
            const double d = luminance(glm::vec3(img.pixels[i].rgba)) - luminance(glm::vec3(truth.pixels[i].rgba));
            sum += d * d;
        }
    }
    const double rmse = std::sqrt(sum / double(n));
    std::printf("%s, 16 spp: RMSE %.6f, previously %.6f: variance / %.2f\n", what, rmse, previous_rmse,
                (previous_rmse / rmse) * (previous_rmse / rmse));
    EXPECT_LE(rmse, previous_rmse / std::sqrt(factor)) << what;
}

TEST(ReferenceVariance, FallsAtEqualSamples) {
    expectVarianceFallsBy("single_scattering", 1, 0.043473, 3.5);
    expectVarianceFallsBy("multiple_scattering", 16, 0.051530, 2.0);
}

// Less albedo, less light: the mean image falls strictly, with the same seed (and paths).
TEST(Reference, EnergyFallsWithAlbedo) {
    Ball b = ball("reference_energy");
    b.scene.render.reference.spp = 32;
    b.scene.lights.push_back(ambientLight(0.5f));
    double previous = INFINITY;
    for (float albedo : {1.0f, 0.8f, 0.5f, 0.2f}) {
        b.scene.volume().material.albedo = glm::vec3(albedo);
        auto prepared = prepare(b.volume, b.scene, *b.scene.camera);
        const double mean = meanLuminance(renderReference(prepared->inputs, b.scene.render.reference));
        std::printf("albedo %.1f: mean luminance %.5f\n", albedo, mean);
        EXPECT_LT(mean, previous) << "albedo " << albedo;
        previous = mean;
    }
}

// Tracking stays bounded in any medium. At density 3e38 the majorant overflowed a float, and
// delta tracking neither moved nor collided (it never finished); at 1e6, loose majorants (bricks
// the trilinear ramp reaches beyond the last voxel) took millions of events per segment. Such
// segments are taken as opaque and counted; the image is opaque and finite either way.
TEST(Reference, ExtremeDensityStaysBoundedAndFinite) {
    for (const float sigma : {1e6f, 3e38f}) {
        Scene scene = referenceScene(2, 1);
        Light key;
        key.direction = glm::normalize(glm::vec3(1, -1, 0));
        key.intensity = 5.0f;
        scene.lights = {key};
        const glm::vec3 centre(float((kN - 1) * 0.5 * kVoxel));
        auto prepared = prepare(volumeFromGrid(boxGrid({0, 0, 0}, {kN - 1, kN - 1, kN - 1}, sigma, kVoxel)), scene,
                                cameraAlong(centre, {0, 0, 1}, 100.0f, 5.0f));
        uint64_t opaque = 0;
        const RenderImage img = renderReference(prepared->inputs, scene.render.reference, &opaque);
        for (const auto& p : img.pixels) {
            EXPECT_TRUE(std::isfinite(p.rgba.x + p.rgba.y + p.rgba.z)) << sigma;
            EXPECT_EQ(p.rgba.w, 1.0f) << sigma;
        }
        std::printf("density %g: %llu brick segments taken as opaque\n", double(sigma), (unsigned long long)opaque);
        if (sigma > 1e37f) {
            EXPECT_GT(opaque, 0u);
        }
    }
}

TEST(Reference, DeterministicPerSeed) {
    Ball b = ball("reference_seed");
    b.scene.render.reference.spp = 16;
    b.scene.lights.push_back(ambientLight(0.5f));
    auto prepared = prepare(b.volume, b.scene, *b.scene.camera);
    const RenderImage a = renderReference(prepared->inputs, b.scene.render.reference);
    const RenderImage again = renderReference(prepared->inputs, b.scene.render.reference);
    ReferenceSettings other = b.scene.render.reference;
    other.seed = 2;
    const RenderImage reseeded = renderReference(prepared->inputs, other);
    const size_t bytes = a.pixels.size() * sizeof(kernel::VxPixel);
    EXPECT_EQ(std::memcmp(a.pixels.data(), again.pixels.data(), bytes), 0);
    EXPECT_NE(std::memcmp(a.pixels.data(), reseeded.pixels.data(), bytes), 0);
}

// From the command line: --method reference --spp N renders, and the variance AOV is written.
TEST(Reference, CliWritesTheVarianceAov) {
    const std::string dir = tempDir("reference_cli");
    const std::string vdb = writeBall(dir), exr = dir + "/ref.exr";
    const CliResult r = runCli("render " + vdb + " --method reference --spp 8 --res 8x8 --pixel-type float --aovs variance -o " + exr);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Exr image = readExr(exr);
    ASSERT_EQ(image.planes.count("variance.Y"), 1u);
    float largest = 0.0f;
    for (float v : image.planes.at("variance.Y")) {
        EXPECT_GE(v, 0.0f);
        largest = std::max(largest, v);
    }
    EXPECT_GT(largest, 0.0f);  // 8 samples of a lit ball are not all equal
}

TEST(Reference, SceneKeys) {
    const Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "render": {"method": "reference",
        "reference": {"spp": 8, "max_bounces": 1, "seed": 5, "roulette_depth": 2}}})", "shot.json", "/shots");
    EXPECT_EQ(s.render.method, RenderMethod::Reference);
    EXPECT_EQ(s.render.reference.spp, 8);
    EXPECT_EQ(s.render.reference.max_bounces, 1);
    EXPECT_EQ(s.render.reference.seed, 5);
    EXPECT_EQ(s.render.reference.roulette_depth, 2);
    const Scene back = parseScene(sceneToJson(s).dump(), "shot.json", "");
    EXPECT_EQ(back.render.method, RenderMethod::Reference);
    EXPECT_EQ(back.render.reference.spp, 8);
    EXPECT_EQ(back.render.reference.seed, 5);
    const Scene defaults = parseScene(R"({"volume": {"path": "a.vdb"}})", "shot.json", "");
    EXPECT_EQ(defaults.render.method, RenderMethod::March);
    EXPECT_EQ(defaults.render.reference.spp, 64);
    EXPECT_EQ(defaults.render.reference.max_bounces, 16);
    EXPECT_EQ(defaults.render.reference.roulette_depth, 3);

    const std::string v = R"({"volume": {"path": "a.vdb"}, "render": )";
    EXPECT_EQ(sceneErrorOf(v + R"({"method": "path"}})"), "shot.json: /render/method: 'path' is not one of march, reference");
    EXPECT_EQ(sceneErrorOf(v + R"({"method": "reference", "reference": {"spp": 0}}})"),
              "shot.json: /render/reference/spp: must lie in 1..1000000");
    EXPECT_EQ(sceneErrorOf(v + R"({"method": "reference", "backend": "gl"}})"),
              "shot.json: /render/method: reference runs on the cpu backend only (render.backend is \"gl\")");
    EXPECT_EQ(sceneErrorOf(v + R"({"method": "reference"}, "effects": {"surface": true}})"),
              "shot.json: /effects: surface and perturbation are march-only effects (render.method is \"reference\")");
}

}  // namespace
}  // namespace voxlux::test
