// The reference's variance at equal samples per pixel, against the estimators it replaced (delta
// tracking from the camera, plain ratio tracking, binary escapes, independent random numbers),
// whose RMSE here this same test measured at commit 354cdc6. Both are unbiased, so each is
// measured against a 4096-spp render of itself. docs/accuracy.md gives the factors, and the
// seconds on the study scenes and against Cycles.
#include <cmath>
#include <cstdio>

#include "reference/reference_renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

double luminance(glm::vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// A small noisy ball under a sun and a sky.
struct Lit {
    Scene scene;
    LoadedVolume volume;
};

Lit litBall(const std::string& folder, int max_bounces, float albedo) {
    Lit b;
    b.scene.render.width = b.scene.render.height = 16;
    b.scene.render.method = RenderMethod::Reference;
    b.scene.render.reference.max_bounces = max_bounces;
    b.scene.material.density_scale = 1.5f;
    b.scene.material.anisotropy = 0.3f;
    b.scene.material.albedo = glm::vec3(albedo);
    Light sun, sky;
    sun.direction = glm::vec3(-1.0f, -0.5f, -0.7f);
    sun.intensity = 3.0f;
    sky.type = LightType::Ambient;
    sky.intensity = 0.5f;
    b.scene.lights = {sun, sky};
    b.scene.camera = cameraAlong(glm::vec3(0.0f), {0.2f, -0.1f, -1.0f}, 8.0f, 32.0f);
    b.volume = loadVolume(writeBall(tempDir(folder)), b.scene.volume);
    return b;
}

// RMSE of the beauty's luminance at `spp` against 4096 spp, over 8 seeds (its square's mean).
double rmseAt(Lit& b, int spp) {
    auto prepared = prepare(b.volume, b.scene, *b.scene.camera);
    ReferenceSettings rs = b.scene.render.reference;
    rs.spp = 4096;
    rs.seed = 1000;
    const RenderImage truth = renderReference(prepared->inputs, rs);
    double sum = 0.0;
    size_t n = 0;
    for (int seed = 1; seed <= 8; ++seed) {
        rs.spp = spp;
        rs.seed = seed;
        const RenderImage img = renderReference(prepared->inputs, rs);
        for (size_t i = 0; i < img.pixels.size(); ++i, ++n) {
            const double d = luminance(glm::vec3(img.pixels[i].rgba)) - luminance(glm::vec3(truth.pixels[i].rgba));
            sum += d * d;
        }
    }
    return std::sqrt(sum / double(n));
}

// The RMSE at 16 spp is at most the previous estimators' over sqrt(factor): their variance over
// `factor`.
void expectVarianceFallsBy(const char* what, int max_bounces, double previous_rmse, double factor) {
    Lit b = litBall(std::string("variance_") + what, max_bounces, 0.9f);
    const double rmse = rmseAt(b, 16);
    std::printf("%s, 16 spp: RMSE %.6f, previously %.6f: variance / %.2f\n", what, rmse, previous_rmse,
                (previous_rmse / rmse) * (previous_rmse / rmse));
    EXPECT_LE(rmse, previous_rmse / std::sqrt(factor)) << what;
}

// Measured: variance / 3.9 in single scattering, / 2.1 in multiple scattering (albedo 0.9, up to
// 16 bounces).
TEST(ReferenceVariance, FallsAtEqualSamples) {
    expectVarianceFallsBy("single_scattering", 1, 0.043473, 3.5);
    expectVarianceFallsBy("multiple_scattering", 16, 0.051530, 2.0);
}

}  // namespace
}  // namespace voxlux::test
