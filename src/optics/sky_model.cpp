#include "optics/sky_model.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

#include "optics/environment_map.h"

namespace voxlux {

namespace {


// Perez et al.'s five coefficients, linear in turbidity T (Preetham et al. 1999, Appendix A.2).
struct Perez {
    double a, b, c, d, e;
    double operator()(double cos_theta, double gamma) const {
        const double cos_gamma = std::cos(gamma);
        return (1.0 + a * std::exp(b / std::max(cos_theta, 0.01))) * (1.0 + c * std::exp(d * gamma) + e * cos_gamma * cos_gamma);
    }
};

Perez luminanceCoefficients(double t) {
    return {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771, -0.0670 * t + 0.3703};
}
Perez xCoefficients(double t) {
    return {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989, -0.0033 * t + 0.0452};
}
Perez yCoefficients(double t) {
    return {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537, -0.0109 * t + 0.0529};
}

// The zenith's chromaticity: a cubic in the sun's zenith angle per power of turbidity (Appendix A.2).
double zenithChromaticity(const double (&m)[3][4], double t, double theta_s) {
    const double powers[4] = {theta_s * theta_s * theta_s, theta_s * theta_s, theta_s, 1.0};
    const double turbidity[3] = {t * t, t, 1.0};
    double sum = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) sum += turbidity[i] * m[i][j] * powers[j];
    return sum;
}

glm::dvec3 xyYToXyz(double x, double y, double luminance) {
    return {x / y * luminance, luminance, (1.0 - x - y) / y * luminance};
}

// The clear sky's radiance towards unit direction `w` (z up) in XYZ, 10 kcd/m^2 units.
class ClearSky {
public:
    ClearSky(glm::dvec3 sun, double turbidity) : sun_(sun), lum_(luminanceCoefficients(turbidity)), x_(xCoefficients(turbidity)), y_(yCoefficients(turbidity)) {
        const double theta_s = std::acos(std::clamp(sun.z, -1.0, 1.0));
        const double t = turbidity;
        const double chi = (4.0 / 9.0 - t / 120.0) * (glm::pi<double>() - 2.0 * theta_s);
        zenith_luminance_ = std::max(((4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192) / 10.0, 0.0);   // kcd -> 10 kcd
        static const double mx[3][4] = {{0.00166, -0.00375, 0.00209, 0.0}, {-0.02903, 0.06377, -0.03202, 0.00394}, {0.11693, -0.21196, 0.06052, 0.25886}};
        static const double my[3][4] = {{0.00275, -0.00610, 0.00317, 0.0}, {-0.04214, 0.08970, -0.04153, 0.00516}, {0.15346, -0.26756, 0.06670, 0.26688}};
        zenith_x_ = zenithChromaticity(mx, t, theta_s);
        zenith_y_ = zenithChromaticity(my, t, theta_s);
        theta_s_ = theta_s;
    }
    glm::dvec3 operator()(glm::dvec3 w) const {
        const double gamma = std::acos(std::clamp(glm::dot(w, sun_), -1.0, 1.0));
        const double cos_theta = std::max(w.z, 0.0);
        const auto relative = [&](const Perez& p) { return p(cos_theta, gamma) / p(1.0, theta_s_); };
        return xyYToXyz(zenith_x_ * relative(x_), zenith_y_ * relative(y_), zenith_luminance_ * relative(lum_));
    }

private:
    glm::dvec3 sun_;
    Perez lum_, x_, y_;
    double zenith_luminance_ = 0.0, zenith_x_ = 0.0, zenith_y_ = 0.0, theta_s_ = 0.0;
};

// The sun's illuminance on a surface facing it, XYZ in 10 klx: 100 klx outside the atmosphere's
// scattering, dimmed and reddened by an extinction per channel through Kasten and Young's air mass.
glm::dvec3 sunIlluminance(double elevation_degrees, double turbidity) {
    const double zenith = 90.0 - std::max(elevation_degrees, 0.0);
    const double air_mass = 1.0 / (std::cos(zenith * glm::pi<double>() / 180.0) + 0.50572 * std::pow(96.07995 - zenith, -1.6364));
    const glm::dvec3 optical_depth = glm::dvec3(0.08, 0.12, 0.26) * (turbidity / 3.0);   // X, Y, Z: blue scatters most
    return glm::dvec3(9.5, 10.0, 10.9) * glm::exp(-optical_depth * air_mass);
}

}  // namespace

glm::vec3 sunDirection(const SkyParams& p) {
    const double e = glm::radians(double(p.sun_elevation)), a = glm::radians(double(p.sun_azimuth));
    return glm::vec3(float(std::cos(e) * std::cos(a)), float(std::cos(e) * std::sin(a)), float(std::sin(e)));
}

std::vector<glm::vec3> makeSky(const SkyParams& p) {
    // The map in its own frame (z up, rotation 0): its directions are the sky model's.
    const EnvironmentMap frame(p.width, p.height, std::vector<glm::vec3>(size_t(p.width) * p.height), {0, 0, 1}, 0.0f);
    const glm::dvec3 sun(sunDirection(p));
    const ClearSky clear(sun, p.turbidity);
    std::vector<glm::dvec3> sky(size_t(p.width) * p.height);
    for (int y = 0; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x) {
            const glm::dvec3 w(frame.pixelDirection(x, y));
            if (w.z < 0.0) continue;
            sky[size_t(y) * p.width + x] = p.kind == SkyKind::Clear ? clear(w) : glm::dvec3(0.9505, 1.0, 1.089) * (0.4 * (1.0 + 2.0 * w.z) / 3.0);
        }
    // The sun: its illuminance in the pixel it falls in (the ground below is lit by it either way).
    glm::dvec3 sun_light(0.0);
    glm::ivec2 sun_pixel(-1);
    if (p.kind == SkyKind::Clear && p.sun_elevation > 0.0f) {
        sun_light = sunIlluminance(p.sun_elevation, p.turbidity);
        sun_pixel = frame.pixelOf(glm::vec3(sun));
        if (p.sun_disc) sky[size_t(sun_pixel.y) * p.width + sun_pixel.x] += sun_light / frame.pixelSolidAngle(sun_pixel.y);
    }
    // The ground: Lambertian, lit by the sky above and the sun.
    glm::dvec3 horizontal(0.0);
    for (int y = 0; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x) {
            const glm::dvec3 w(frame.pixelDirection(x, y));
            if (w.z > 0.0 && glm::ivec2(x, y) != sun_pixel) horizontal += sky[size_t(y) * p.width + x] * (w.z * frame.pixelSolidAngle(y));
        }
    horizontal += sun_light * std::max(sun.z, 0.0);
    const glm::dvec3 ground = horizontal * (double(p.ground_albedo) / glm::pi<double>());
    std::vector<glm::vec3> out(sky.size());
    for (int y = 0; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x) {
            const size_t i = size_t(y) * p.width + x;
            out[i] = glm::vec3(frame.pixelDirection(x, y).z < 0.0f ? ground : sky[i]);
        }
    return out;
}

}  // namespace voxlux
