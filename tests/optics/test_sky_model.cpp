// The skies of `voxlux make-sky` (optics/sky_model.h): the sun in the pixel of its elevation and
// azimuth, carrying its illuminance; a clear zenith bluer than the horizon (Preetham's chromaticity);
// the CIE overcast sky three times brighter at the zenith than at the horizon; the ground a
// Lambertian reflector of everything above it (brute force).
#include <cmath>

#include <gtest/gtest.h>

#include "optics/environment_map.h"
#include "optics/sky_model.h"

namespace voxlux {
namespace {

constexpr int kW = 128, kH = 64;

EnvironmentMap mapOf(const SkyParams& p) { return EnvironmentMap(p.width, p.height, makeSky(p), {0, 0, 1}, 0.0f); }

SkyParams params(SkyKind kind) {
    SkyParams p;
    p.kind = kind;
    p.width = kW;
    p.height = kH;
    p.sun_elevation = 30.0f;
    p.sun_azimuth = 90.0f;
    return p;
}

TEST(SkyModel, TheSunSitsInThePixelOfItsElevationAndAzimuth) {
    const SkyParams p = params(SkyKind::Clear);
    const EnvironmentMap sky = mapOf(p);
    // 30 degrees up, 90 degrees from the centre column: the left quarter's column, a third of the
    // way from the horizon to the zenith.
    const glm::vec3 sun = sunDirection(p);
    EXPECT_LT(glm::length(sun - glm::vec3(0.0f, std::cos(glm::radians(30.0f)), 0.5f)), 1e-6f);
    glm::ivec2 brightest(0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (sky.at({x, y}).y > sky.at(brightest).y) brightest = {x, y};
    EXPECT_EQ(brightest, sky.pixelOf(sun));
    EXPECT_EQ(brightest, glm::ivec2(kW / 4, int((90.0 - 30.0) / 180.0 * kH)));
    // Its illuminance: about 10 (100 klx dimmed by the air mass of 2 at 30 degrees).
    const double sun_y = sky.at(brightest).y * sky.pixelSolidAngle(brightest.y);
    EXPECT_GT(sun_y, 6.0);
    EXPECT_LT(sun_y, 10.0);
    // Without its disc the sky is the same but for the sun's pixel, and the ground still sees the sun.
    SkyParams no_disc = p;
    no_disc.sun_disc = false;
    const EnvironmentMap sky_alone = mapOf(no_disc);
    EXPECT_LT(sky_alone.at(brightest).y, 0.01 * sky.at(brightest).y);
    EXPECT_EQ(sky_alone.at({0, 0}), sky.at({0, 0}));
    EXPECT_EQ(sky_alone.at({0, kH - 1}), sky.at({0, kH - 1}));
}

TEST(SkyModel, AClearZenithIsBluerThanItsHorizon) {
    const EnvironmentMap sky = mapOf(params(SkyKind::Clear));
    const glm::vec3 zenith = sky.at({kW / 2, 0}), horizon = sky.at({kW * 3 / 4, kH / 2 - 1});   // away from the sun
    EXPECT_GT(zenith.z / zenith.y, 1.2f * horizon.z / horizon.y);
    EXPECT_GT(zenith.y, 0.1f);
    EXPECT_LT(zenith.y, 2.0f);
}

TEST(SkyModel, TheOvercastSkyIsThreeTimesBrighterAtTheZenithThanAtTheHorizon) {
    const EnvironmentMap sky = mapOf(params(SkyKind::Overcast));
    const float zenith = sky.at({0, 0}).y, horizon = sky.at({0, kH / 2 - 1}).y;
    const double cos_zenith = std::cos(M_PI * 0.5 / kH), cos_horizon = std::cos(M_PI * (kH / 2 - 0.5) / kH);
    EXPECT_NEAR(zenith / horizon, (1.0 + 2.0 * cos_zenith) / (1.0 + 2.0 * cos_horizon), 1e-4);
    for (int x = 0; x < kW; ++x) EXPECT_EQ(sky.at({x, 5}), sky.at({0, 5})) << "no sun, no azimuth";
}

TEST(SkyModel, TheGroundReflectsTheSkyAndTheSunAboveIt) {
    for (SkyKind kind : {SkyKind::Clear, SkyKind::Overcast}) {
        SkyParams p = params(kind);
        p.ground_albedo = 0.25f;
        const EnvironmentMap sky = mapOf(p);
        // Everything above the horizon (the sun's pixel included) weighted by its cosine.
        double horizontal = 0.0;
        const glm::ivec2 sun = sky.pixelOf(sunDirection(p));
        for (int y = 0; y < kH / 2; ++y)
            for (int x = 0; x < kW; ++x) {
                const bool sun_pixel = kind == SkyKind::Clear && glm::ivec2(x, y) == sun;
                const double cosine = sun_pixel ? double(sunDirection(p).z) : double(sky.pixelDirection(x, y).z);
                horizontal += sky.at({x, y}).y * sky.pixelSolidAngle(y) * cosine;
            }
        EXPECT_NEAR(sky.at({3, kH - 4}).y, 0.25 * horizontal / M_PI, 1e-4 * horizontal) << int(kind);
    }
}

}  // namespace
}  // namespace voxlux
