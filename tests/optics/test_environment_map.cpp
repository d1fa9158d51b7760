// An environment light's map (optics/environment_map.h) and its median cut (optics/median_cut.h):
// the orientation convention (Blender's equirectangular mapping with z up), the solid angles, the
// importance sampling's density, and the cut's lights against brute force: their power sums to
// the map's, each sits at its region's power centroid, and a floor leaves a constant map to ambient.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "optics/environment_map.h"
#include "optics/median_cut.h"

namespace voxlux {
namespace {

void expectDirection(glm::vec3 got, glm::vec3 expected, const char* what) {
    EXPECT_LT(glm::length(got - expected), 1e-5f) << what << ": (" << got.x << ", " << got.y << ", " << got.z << ")";
}

std::vector<glm::vec3> patternedMap(int width, int height) {
    std::vector<glm::vec3> pixels(size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            pixels[size_t(y) * width + x] = glm::vec3(0.1f + 0.05f * float((x * 7 + y * 3) % 5), 0.2f + 0.01f * float(x), 0.3f + 0.1f * float(y));
    pixels[size_t(3) * width + 5] = glm::vec3(40.0f, 30.0f, 20.0f);   // a sun
    return pixels;
}

TEST(EnvironmentMap, FollowsBlendersEquirectangularMappingWithZUp) {
    const EnvironmentMap z_up(8, 4, std::vector<glm::vec3>(32, glm::vec3(1.0f)), {0, 0, 1}, 0.0f);
    expectDirection(z_up.direction({0.5f, 0.0f}), {0, 0, 1}, "top row");
    expectDirection(z_up.direction({0.5f, 1.0f}), {0, 0, -1}, "bottom row");
    expectDirection(z_up.direction({0.5f, 0.5f}), {1, 0, 0}, "centre");
    expectDirection(z_up.direction({0.25f, 0.5f}), {0, 1, 0}, "left quarter");
    expectDirection(z_up.direction({0.0f, 0.5f}), {-1, 0, 0}, "left edge");
    // Y up: the frame Blender's z-up scene takes when exported y up (z -> y, y -> -z).
    const EnvironmentMap y_up(8, 4, std::vector<glm::vec3>(32, glm::vec3(1.0f)), {0, 1, 0}, 0.0f);
    expectDirection(y_up.direction({0.5f, 0.0f}), {0, 1, 0}, "y up: top row");
    expectDirection(y_up.direction({0.5f, 0.5f}), {1, 0, 0}, "y up: centre");
    expectDirection(y_up.direction({0.25f, 0.5f}), {0, 0, -1}, "y up: left quarter");
    // A rotation of 90 degrees turns the centre counter-clockwise about up, seen from above.
    const EnvironmentMap turned(8, 4, std::vector<glm::vec3>(32, glm::vec3(1.0f)), {0, 0, 1}, 90.0f);
    expectDirection(turned.direction({0.5f, 0.5f}), {0, 1, 0}, "turned 90: centre");
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) EXPECT_EQ(turned.pixelOf(turned.pixelDirection(x, y)), glm::ivec2(x, y));
}

// The camera's view of the map is bilinear between pixel centres, and wraps across the seam.
TEST(EnvironmentMap, FilteredLookupsInterpolateBetweenPixelCentres) {
    const EnvironmentMap map(16, 8, patternedMap(16, 8), {0, 1, 0}, 0.0f);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) EXPECT_LT(glm::length(map.filtered(map.pixelDirection(x, y)) - map.at({x, y})), 1e-4f);
    const glm::vec3 between = map.filtered(map.direction({6.0f / 16.0f, 3.5f / 8.0f}));
    EXPECT_LT(glm::length(between - 0.5f * (map.at({5, 3}) + map.at({6, 3}))), 1e-4f);
    const glm::vec3 seam = map.filtered(map.direction({0.0f, 2.5f / 8.0f}));
    EXPECT_LT(glm::length(seam - 0.5f * (map.at({15, 2}) + map.at({0, 2}))), 1e-4f);
}

TEST(EnvironmentMap, SolidAnglesCoverTheSphereAndAConstantMapCarries4PiL) {
    const EnvironmentMap map(64, 32, std::vector<glm::vec3>(64 * 32, glm::vec3(0.5f, 1.0f, 2.0f)), {0, 1, 0}, 0.0f);
    double sphere = 0.0;
    for (int y = 0; y < 32; ++y) sphere += map.pixelSolidAngle(y) * 64;
    EXPECT_NEAR(sphere, 4.0 * M_PI, 1e-9);
    const glm::dvec3 power = map.power();
    EXPECT_NEAR(power.x, 4.0 * M_PI * 0.5, 1e-6);
    EXPECT_NEAR(power.z, 4.0 * M_PI * 2.0, 1e-6);
}

// Sampling draws a pixel in proportion to luminance x solid angle: radiance over density is then the
// map's total luminance power for every sample, and pdf() gives sample()'s density.
TEST(EnvironmentMap, SamplesInProportionToLuminanceTimesSolidAngle) {
    const EnvironmentMap map(16, 8, patternedMap(16, 8), {0, 1, 0}, 30.0f);
    double total = 0.0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) total += double(environmentLuminance(map.at({x, y}))) * map.pixelSolidAngle(y);
    int sun = 0;
    constexpr int kSamples = 4096;
    for (int i = 0; i < kSamples; ++i) {
        float pdf = 0.0f;
        const glm::vec3 w = map.sample({(float(i % 64) + 0.5f) / 64.0f, (float(i / 64) + 0.5f) / 64.0f}, pdf);
        ASSERT_GT(pdf, 0.0f);
        EXPECT_NEAR(pdf, map.pdf(w), 1e-6f * pdf);
        EXPECT_NEAR(environmentLuminance(map.lookup(w)) / pdf, total, 1e-4 * total);
        sun += map.pixelOf(w) == glm::ivec2(5, 3);
    }
    const double sun_share = double(environmentLuminance(map.at({5, 3}))) * map.pixelSolidAngle(3) / total;
    EXPECT_NEAR(double(sun) / kSamples, sun_share, 2.0 / 64.0);   // the sample grid has 64 rows

    // Pearson's chi-square over the pixels, 200000 independent draws: below the 0.999 quantile
    // of 127 degrees of freedom (181.9). Within a pixel the directions are uniform in solid angle:
    // the mean cosine of the sun pixel's draws is its middle in cos theta.
    std::vector<double> counts(16 * 8, 0.0);
    uint64_t state = 12345;
    const auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(double(state >> 40) / double(1ull << 24));
    };
    constexpr int kDraws = 200000;
    double sun_cosines = 0.0;
    int sun_draws = 0;
    for (int i = 0; i < kDraws; ++i) {
        float pdf = 0.0f;
        const glm::vec3 w = map.sample({next(), next()}, pdf);
        const glm::ivec2 p = map.pixelOf(w);
        counts[size_t(p.y) * 16 + size_t(p.x)] += 1.0;
        if (p == glm::ivec2(5, 3)) {
            sun_cosines += double(glm::dot(w, map.frame()[2]));
            ++sun_draws;
        }
    }
    double chi2 = 0.0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            const double expected = kDraws * double(environmentLuminance(map.at({x, y}))) * map.pixelSolidAngle(y) / total;
            chi2 += (counts[size_t(y) * 16 + size_t(x)] - expected) * (counts[size_t(y) * 16 + size_t(x)] - expected) / expected;
        }
    EXPECT_LT(chi2, 181.9);
    const double middle = 0.5 * (std::cos(M_PI * 3.0 / 8.0) + std::cos(M_PI * 4.0 / 8.0));
    EXPECT_NEAR(sun_cosines / sun_draws, middle, 0.002);
}

TEST(MedianCut, LightsCarryTheMapsPowerFromTheirRegionsPowerCentroids) {
    const EnvironmentMap map(16, 8, patternedMap(16, 8), {0, 0, 1}, 0.0f);
    for (bool floor : {false, true}) {
        for (int k : {1, 5, 16}) {
            const MedianCut cut = medianCut(map, k, floor);
            ASSERT_EQ(int(cut.lights.size()), k);
            glm::dvec3 sum = glm::dvec3(cut.ambient) * (4.0 * M_PI);
            int pixels = 0;
            for (const CutLight& l : cut.lights) {
                sum += glm::dvec3(l.irradiance);
                // Brute force: the luminance-above-the-floor x solid-angle weighted mean of the
                // region's pixel directions, and its radiance above the floor x solid angle.
                glm::dvec3 centroid(0.0), irradiance(0.0);
                for (int y = l.region.y; y < l.region.w; ++y)
                    for (int x = l.region.x; x < l.region.z; ++x) {
                        const glm::vec3 above = map.at({x, y}) - cut.ambient;
                        centroid += glm::dvec3(map.pixelDirection(x, y)) * (double(environmentLuminance(above)) * map.pixelSolidAngle(y));
                        irradiance += glm::dvec3(above) * map.pixelSolidAngle(y);
                        ++pixels;
                    }
                EXPECT_LT(glm::length(glm::dvec3(l.toward) - glm::normalize(centroid)), 1e-5) << "K " << k;
                EXPECT_LT(glm::length(glm::dvec3(l.irradiance) - irradiance), 1e-5 * glm::length(irradiance)) << "K " << k;
            }
            EXPECT_EQ(pixels, 16 * 8) << "the regions tile the map";
            const glm::dvec3 power = map.power();
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], power[c], 1e-5 * power[c]) << "K " << k << " floor " << floor;
        }
    }
    // The sun's pixel is a region of its own once K reaches a few lights: its power exceeds a half
    // of the rest, so each split gives it a smaller region.
    const MedianCut eight = medianCut(map, 16, true);
    EXPECT_TRUE(std::any_of(eight.lights.begin(), eight.lights.end(), [](const CutLight& l) { return l.region == glm::ivec4(5, 3, 6, 4); }));
}

// A map whose light is near the zenith and the horizon alike: every one of the K regions carries
// light (none splits into an empty half and itself again), on a 2:1 map whose pixels span equal
// angles at the equator.
TEST(MedianCut, EveryRegionCarriesLightWhereverTheLightIs) {
    constexpr int kW = 64, kH = 32;
    std::vector<glm::vec3> pixels(size_t(kW) * kH, glm::vec3(0.01f));
    pixels[size_t(1) * kW + 20] = glm::vec3(500.0f);        // a sun near the zenith
    pixels[size_t(kH / 2) * kW + 50] = glm::vec3(200.0f);   // one on the horizon
    const EnvironmentMap map(kW, kH, pixels, {0, 0, 1}, 0.0f);
    for (int k : {2, 8, 32, 128}) {
        const MedianCut cut = medianCut(map, k, false);
        ASSERT_EQ(int(cut.lights.size()), k);
        for (const CutLight& l : cut.lights) {
            EXPECT_GT(l.region.z, l.region.x);
            EXPECT_GT(l.region.w, l.region.y);
            EXPECT_GT(l.irradiance.x, 0.0f) << "K " << k << ": region " << l.region.x << "," << l.region.y << "-" << l.region.z << "," << l.region.w;
        }
    }
}

TEST(MedianCut, AConstantMapIsAllAmbientUnderAFloor) {
    const EnvironmentMap map(32, 16, std::vector<glm::vec3>(32 * 16, glm::vec3(0.25f, 0.5f, 1.0f)), {0, 1, 0}, 0.0f);
    const MedianCut cut = medianCut(map, 16, true);
    EXPECT_EQ(cut.ambient, glm::vec3(0.25f, 0.5f, 1.0f));
    for (const CutLight& l : cut.lights) EXPECT_EQ(l.irradiance, glm::vec3(0.0f));
    const MedianCut none = medianCut(map, 0, false);
    EXPECT_TRUE(none.lights.empty());
    EXPECT_EQ(none.ambient, glm::vec3(0.0f));
}

}  // namespace
}  // namespace voxlux
