// Blackbody colour against published CIE 1931 Planckian-locus values, the colour-matching table
// against its own normalisation, and luminance against a brute-force integral written here.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "optics/blackbody.h"

namespace voxlux::test {
namespace {

// Planck's law in the textbook form (no overflow guard needed at the temperatures used here).
double planckRadiance(double metres, double kelvin) {
    const double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23;
    return 2.0 * h * c * c / std::pow(metres, 5) / (std::exp(h * c / (metres * kelvin * k)) - 1.0);
}

// Y of a blackbody by the midpoint rule at 0.1 nm over the linearly interpolated table.
double bruteForceY(double kelvin) {
    double sum = 0.0;
    for (int i = 0; i < 4700; ++i) {
        const double nm = 360.0 + 0.1 * (i + 0.5);
        sum += planckRadiance(nm * 1e-9, kelvin) * cieColourMatching(nm).y;
    }
    return sum * 0.1e-9;
}

TEST(Blackbody, ChromaticityMatchesPublishedPlanckianLocus) {
    // CIE 1931 2 degree Planckian locus to 4 decimals, as tabulated in J. Walker's "Colour
    // Rendering of Spectra" (fourmilab.ch). His 6500 K y is 0.3237 because he sums 380..780 nm
    // only (that reproduces 0.32367 here); over 360..830 nm it is 0.32363.
    struct Published {
        double kelvin, x, y;
    };
    for (const Published p : {Published{1000, 0.6528, 0.3444}, Published{3000, 0.4369, 0.4041},
                              Published{6500, 0.3135, 0.3236}, Published{10000, 0.2807, 0.2884}}) {
        const glm::dvec2 xy = blackbodyChromaticity(p.kelvin);
        std::printf("  %5.0f K: x %.5f y %.5f, error %+.5f %+.5f\n", p.kelvin, xy.x, xy.y, xy.x - p.x, xy.y - p.y);
        EXPECT_NEAR(xy.x, p.x, 0.005) << p.kelvin << " K";
        EXPECT_NEAR(xy.y, p.y, 0.005) << p.kelvin << " K";
        // The published values are rounded to 4 decimals: anything past that is a table typo.
        EXPECT_NEAR(xy.x, p.x, 0.0005) << p.kelvin << " K";
        EXPECT_NEAR(xy.y, p.y, 0.0005) << p.kelvin << " K";
    }
}

TEST(Blackbody, ColourMatchingTableIntegratesToEqualEnergyWhite) {
    // The CIE normalised the functions so a flat spectrum has X = Y = Z; a mistyped row breaks it.
    glm::dvec3 integral(0.0);
    for (int nm = 360; nm <= 830; nm += 5)
        integral += (nm == 360 || nm == 830 ? 2.5 : 5.0) * cieColourMatching(nm);
    EXPECT_NEAR(integral.x / integral.y, 1.0, 1e-3);
    EXPECT_NEAR(integral.z / integral.y, 1.0, 1e-3);
    // The 1 nm CIE table sums ybar to 106.8569 (the photometric normalisation).
    EXPECT_NEAR(integral.y, 106.857, 0.01);
    EXPECT_EQ(cieColourMatching(555.0).y, 1.0);
    EXPECT_EQ(cieColourMatching(600.0), glm::dvec3(1.0622, 0.631, 0.0008));
    EXPECT_EQ(cieColourMatching(359.9), glm::dvec3(0.0));
    EXPECT_EQ(cieColourMatching(830.1), glm::dvec3(0.0));
}

TEST(Blackbody, LuminanceRisesWithTemperatureAndMatchesBruteForce) {
    double previous = 0.0;
    for (double kelvin = 1000.0; kelvin <= 20000.0; kelvin += 250.0) {
        const double y = blackbodyXYZ(kelvin).y;
        EXPECT_GT(y, previous) << kelvin << " K";
        previous = y;
    }
    const double ratio = blackbodyXYZ(2000.0).y / blackbodyXYZ(1000.0).y;
    const double expected = bruteForceY(2000.0) / bruteForceY(1000.0);
    std::printf("  Y(2000 K) / Y(1000 K) = %.2f, brute force %.2f\n", ratio, expected);
    EXPECT_NEAR(ratio / expected, 1.0, 1e-3);
    // Absolute scale too: Y is luminance / 683 lm/W.
    EXPECT_NEAR(blackbodyXYZ(1000.0).y / bruteForceY(1000.0), 1.0, 1e-3);
}

TEST(Blackbody, ExtremeTemperatures) {
    EXPECT_EQ(blackbodyXYZ(0.0), glm::dvec3(0.0));
    EXPECT_EQ(blackbodyXYZ(-300.0), glm::dvec3(0.0));
    // Cold bodies' radiance underflows, but their colour tends to the red end of the table; hot
    // bodies' to the Rayleigh-Jeans limit. Neither may overflow into NaN.
    for (double kelvin : {1.0, 10.0, 100.0, 1e5, 1e6}) {
        const glm::dvec3 xyz = blackbodyXYZ(kelvin);
        const glm::dvec2 xy = blackbodyChromaticity(kelvin);
        EXPECT_TRUE(std::isfinite(xyz.x) && std::isfinite(xyz.y) && std::isfinite(xyz.z)) << kelvin << " K";
        EXPECT_TRUE(xy.x > 0.2 && xy.x < 0.74 && xy.y > 0.2 && xy.y < 0.35) << kelvin << " K";
    }
    const glm::dvec3 red_end = cieColourMatching(830.0);
    EXPECT_NEAR(blackbodyChromaticity(1.0).x, red_end.x / (red_end.x + red_end.y), 1e-3);
}

}  // namespace
}  // namespace voxlux::test
