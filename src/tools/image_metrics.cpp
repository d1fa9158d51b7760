#include "tools/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_reduce.h>
#include <tbb/blocked_range.h>

namespace voxlux {
namespace {

void checkSizes(const RenderImage& a, const RenderImage& b) {
    if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size())
        throw std::invalid_argument("image metrics: images of different sizes");
}

// Sum of f(i) over all pixels, in parallel, in double.
template <class F>
double sumOverPixels(size_t n, F f) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, n), 0.0,
        [&](const tbb::blocked_range<size_t>& r, double s) {
            for (size_t i = r.begin(); i != r.end(); ++i) s += f(i);
            return s;
        },
        std::plus<double>());
}

double squaredRgbDifference(const kernel::VxPixel& a, const kernel::VxPixel& b) {
    double s = 0;
    for (int c = 0; c < 3; ++c) {
        const double d = double(a.rgba[c]) - double(b.rgba[c]);
        s += d * d;
    }
    return s;
}

// SMPTE ST 2084 (PQ) inverse EOTF of a luminance in units of 10000 cd/m^2.
double pq(double y) {
    constexpr double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0;
    constexpr double c1 = 3424.0 / 4096.0, c2 = 2413.0 / 4096.0 * 32.0, c3 = 2392.0 / 4096.0 * 32.0;
    const double p = std::pow(std::max(y, 0.0), m1);
    return std::pow((c1 + c2 * p) / (1.0 + c3 * p), m2);
}

// BT.2124's I, T (= Ct / 2) and P (= Cp) of linear Rec.2020 RGB in cd/m^2 (BT.2100 ICtCp).
glm::dvec3 itp(const glm::dvec3& rec2020_nits) {
    const glm::dvec3 rgb = glm::max(rec2020_nits, glm::dvec3(0.0)) / 10000.0;
    const double l = pq((1688.0 * rgb.x + 2146.0 * rgb.y + 262.0 * rgb.z) / 4096.0);
    const double m = pq((683.0 * rgb.x + 2951.0 * rgb.y + 462.0 * rgb.z) / 4096.0);
    const double s = pq((99.0 * rgb.x + 309.0 * rgb.y + 3688.0 * rgb.z) / 4096.0);
    return {0.5 * l + 0.5 * m, 0.5 * (6610.0 * l - 13613.0 * m + 7003.0 * s) / 4096.0,
            (17933.0 * l - 17390.0 * m - 543.0 * s) / 4096.0};
}

}  // namespace

double meanSquaredError(const RenderImage& a, const RenderImage& b) {
    checkSizes(a, b);
    if (a.pixels.empty()) return 0.0;
    return sumOverPixels(a.pixels.size(), [&](size_t i) { return squaredRgbDifference(a.pixels[i], b.pixels[i]); }) /
           (3.0 * double(a.pixels.size()));
}

double halvesNoiseMse(const RenderImage& a, const RenderImage& b) { return meanSquaredError(a, b) / 4.0; }

RenderImage meanOfHalves(const RenderImage& a, const RenderImage& b) {
    checkSizes(a, b);
    RenderImage mean = a;
    for (size_t i = 0; i < mean.pixels.size(); ++i) mean.pixels[i].rgba = 0.5f * (a.pixels[i].rgba + b.pixels[i].rgba);
    return mean;
}

double meanDeltaEItp(const RenderImage& a, const RenderImage& b, const glm::mat3& working_to_xyz, double white_nits) {
    checkSizes(a, b);
    if (a.pixels.empty()) return 0.0;
    // CIE XYZ (D65) to linear Rec.2020 (ITU-R BT.2020 primaries and white).
    const glm::dmat3 xyz_to_rec2020 = glm::transpose(glm::dmat3(1.7166512, -0.3556708, -0.2533663,   //
                                                                -0.6666844, 1.6164812, 0.0157685,    //
                                                                0.0176399, -0.0427706, 0.9421031));
    const glm::dmat3 to_nits = xyz_to_rec2020 * glm::dmat3(working_to_xyz) * white_nits;
    const double sum = sumOverPixels(a.pixels.size(), [&](size_t i) {
        const glm::dvec3 ta = itp(to_nits * glm::dvec3(glm::vec3(a.pixels[i].rgba)));
        const glm::dvec3 tb = itp(to_nits * glm::dvec3(glm::vec3(b.pixels[i].rgba)));
        return 720.0 * glm::length(ta - tb);
    });
    return sum / double(a.pixels.size());
}

}  // namespace voxlux
