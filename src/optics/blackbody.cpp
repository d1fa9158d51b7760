#include "optics/blackbody.h"

#include <algorithm>
#include <cmath>

namespace voxlux {
namespace {

// CIE 1931 2 degree standard observer, 360..830 nm every 5 nm: the 5 nm rows of CIE 018:2019
// "Colour-matching functions of CIE 1931 standard colorimetric observer" (CIE_xyz_1931_2deg.csv,
// the data of CIE 15:2004), {xbar, ybar, zbar}; checked row by row against CVRL's ciexyz31.
constexpr double kFirstNm = 360.0, kTableStepNm = 5.0;
constexpr int kRows = 95;
constexpr double kCmf[kRows][3] = {
    {0.0001299, 0.000003917, 0.0006061},        // 360
    {0.0002321, 0.000006965, 0.001086},
    {0.0004149, 0.00001239, 0.001946},
    {0.0007416, 0.00002202, 0.003486},
    {0.001368, 0.000039, 0.006450001},          // 380
    {0.002236, 0.000064, 0.01054999},
    {0.004243, 0.00012, 0.02005001},
    {0.00765, 0.000217, 0.03621},
    {0.01431, 0.000396, 0.06785001},            // 400
    {0.02319, 0.00064, 0.1102},
    {0.04351, 0.00121, 0.2074},
    {0.07763, 0.00218, 0.3713},
    {0.13438, 0.004, 0.6456},                   // 420
    {0.21477, 0.0073, 1.0390501},
    {0.2839, 0.0116, 1.3856},
    {0.3285, 0.01684, 1.62296},
    {0.34828, 0.023, 1.74706},                  // 440
    {0.34806, 0.0298, 1.7826},
    {0.3362, 0.038, 1.77211},
    {0.3187, 0.048, 1.7441},
    {0.2908, 0.06, 1.6692},                     // 460
    {0.2511, 0.0739, 1.5281},
    {0.19536, 0.09098, 1.28764},
    {0.1421, 0.1126, 1.0419},
    {0.09564, 0.13902, 0.8129501},              // 480
    {0.05795001, 0.1693, 0.6162},
    {0.03201, 0.20802, 0.46518},
    {0.0147, 0.2586, 0.3533},
    {0.0049, 0.323, 0.272},                     // 500
    {0.0024, 0.4073, 0.2123},
    {0.0093, 0.503, 0.1582},
    {0.0291, 0.6082, 0.1117},
    {0.06327, 0.71, 0.07824999},                // 520
    {0.1096, 0.7932, 0.05725001},
    {0.1655, 0.862, 0.04216},
    {0.2257499, 0.9148501, 0.02984},
    {0.2904, 0.954, 0.0203},                    // 540
    {0.3597, 0.9803, 0.0134},
    {0.4334499, 0.9949501, 0.008749999},
    {0.5120501, 1.0, 0.005749999},
    {0.5945, 0.995, 0.0039},                    // 560
    {0.6784, 0.9786, 0.002749999},
    {0.7621, 0.952, 0.0021},
    {0.8425, 0.9154, 0.0018},
    {0.9163, 0.87, 0.001650001},                // 580
    {0.9786, 0.8163, 0.0014},
    {1.0263, 0.757, 0.0011},
    {1.0567, 0.6949, 0.001},
    {1.0622, 0.631, 0.0008},                    // 600
    {1.0456, 0.5668, 0.0006},
    {1.0026, 0.503, 0.00034},
    {0.9384, 0.4412, 0.00024},
    {0.8544499, 0.381, 0.00019},                // 620
    {0.7514, 0.321, 0.0001},
    {0.6424, 0.265, 0.00005},
    {0.5419, 0.217, 0.00003},
    {0.4479, 0.175, 0.00002},                   // 640
    {0.3608, 0.1382, 0.00001},
    {0.2835, 0.107, 0.0},
    {0.2187, 0.0816, 0.0},
    {0.1649, 0.061, 0.0},                       // 660
    {0.1212, 0.04458, 0.0},
    {0.0874, 0.032, 0.0},
    {0.0636, 0.0232, 0.0},
    {0.04677, 0.017, 0.0},                      // 680
    {0.0329, 0.01192, 0.0},
    {0.0227, 0.00821, 0.0},
    {0.01584, 0.005723, 0.0},
    {0.01135916, 0.004102, 0.0},                // 700
    {0.008110916, 0.002929, 0.0},
    {0.005790346, 0.002091, 0.0},
    {0.004109457, 0.001484, 0.0},
    {0.002899327, 0.001047, 0.0},               // 720
    {0.00204919, 0.00074, 0.0},
    {0.001439971, 0.00052, 0.0},
    {0.000999949, 0.0003611, 0.0},
    {0.000690079, 0.0002492, 0.0},              // 740
    {0.000476021, 0.0001719, 0.0},
    {0.000332301, 0.00012, 0.0},
    {0.000234826, 0.0000848, 0.0},
    {0.000166151, 0.00006, 0.0},                // 760
    {0.000117413, 0.0000424, 0.0},
    {0.0000830753, 0.00003, 0.0},
    {0.0000587065, 0.0000212, 0.0},
    {0.0000415099, 0.00001499, 0.0},            // 780
    {0.0000293533, 0.0000106, 0.0},
    {0.0000206738, 0.0000074657, 0.0},
    {0.0000145598, 0.0000052578, 0.0},
    {0.000010254, 0.0000037029, 0.0},           // 800
    {0.00000722146, 0.0000026078, 0.0},
    {0.00000508587, 0.0000018366, 0.0},
    {0.00000358165, 0.0000012934, 0.0},
    {0.00000252253, 0.00000091093, 0.0},        // 820
    {0.00000177651, 0.00000064153, 0.0},
    {0.00000125114, 0.00000045181, 0.0},
};
constexpr double kLastNm = kFirstNm + kTableStepNm * (kRows - 1);

// Planck's radiation constants from the exact SI values of h, c and k.
constexpr double kPlanck = 6.62607015e-34, kLightSpeed = 299792458.0, kBoltzmann = 1.380649e-23;
constexpr double kC1 = 2.0 * kPlanck * kLightSpeed * kLightSpeed;  // 2hc^2, W m^2 sr^-1
constexpr double kC2 = kPlanck * kLightSpeed / kBoltzmann;         // hc/k, m K

// Spectral radiance (W sr^-1 m^-3) at `metres` times e^shift, where shift lets the chromaticity
// of a cold body survive although its radiance underflows. With a = hc/(lambda k T) large,
// e^a would overflow, so use e^-a / (1 - e^-a); with a small (long wavelengths, hot bodies),
// e^a - 1 cancels, so use expm1.
double planckRadiance(double metres, double kelvin, double shift) {
    const double a = kC2 / (metres * kelvin);
    const double c1_over_l5 = kC1 / std::pow(metres, 5);
    if (a > 1.0) return c1_over_l5 * std::exp(shift - a) / -std::expm1(-a);
    return c1_over_l5 * std::exp(shift) / std::expm1(a);
}

// Trapezoid rule at 1 nm over the interpolated table: a 1000 K spectrum changes by a factor of
// e^0.15 over 5 nm, which the rule at 5 nm integrates 0.17% low (0.007% at 1 nm).
constexpr double kStepNm = 1.0;
glm::dvec3 integrateXYZ(double kelvin, double shift) {
    const int steps = int((kLastNm - kFirstNm) / kStepNm);
    glm::dvec3 sum(0.0);
    for (int i = 0; i <= steps; ++i) {
        const double nm = kFirstNm + kStepNm * i;
        const double weight = (i == 0 || i == steps) ? 0.5 : 1.0;
        sum += weight * planckRadiance(nm * 1e-9, kelvin, shift) * cieColourMatching(nm);
    }
    return sum * (kStepNm * 1e-9);
}

}  // namespace

glm::dvec3 cieColourMatching(double nanometres) {
    if (!(nanometres >= kFirstNm && nanometres <= kLastNm)) return glm::dvec3(0.0);
    const double row = (nanometres - kFirstNm) / kTableStepNm;
    const int i = std::min(int(row), kRows - 2);
    const double f = row - i;
    return glm::mix(glm::dvec3(kCmf[i][0], kCmf[i][1], kCmf[i][2]),
                    glm::dvec3(kCmf[i + 1][0], kCmf[i + 1][1], kCmf[i + 1][2]), f);
}

glm::dvec3 blackbodyXYZ(double kelvin) {
    if (kelvin <= 0.0) return glm::dvec3(0.0);
    return integrateXYZ(kelvin, 0.0);
}

glm::dvec2 blackbodyChromaticity(double kelvin) {
    // Scale by the exponent at the longest wavelength, where a cold body radiates most.
    const glm::dvec3 xyz = integrateXYZ(kelvin, kC2 / (kLastNm * 1e-9 * kelvin));
    return glm::dvec2(xyz.x, xyz.y) / (xyz.x + xyz.y + xyz.z);
}

}  // namespace voxlux
