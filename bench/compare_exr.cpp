// voxlux_compare A.exr B.exr: how far B's RGBA is from A's, as the relative RMSE
// (RMSE over A's RMS) and the largest difference, for side-by-side checks of a change against the
// commit before it (docs/performance.md).
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <exception>

#include "io/exr_reader.h"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: voxlux_compare A.exr B.exr\n");
        return 2;
    }
    try {
        const voxlux::RenderImage a = voxlux::readExrRgba(argv[1]), b = voxlux::readExrRgba(argv[2]);
        if (a.width != b.width || a.height != b.height) {
            std::fprintf(stderr, "voxlux_compare: %s is %dx%d, %s is %dx%d\n", argv[1], a.width, a.height, argv[2], b.width,
                         b.height);
            return 2;
        }
        double power = 0.0, error = 0.0, worst = 0.0;
        for (size_t i = 0; i < a.pixels.size(); ++i)
            for (int c = 0; c < 4; ++c) {
                const double x = a.pixels[i].rgba[c], d = x - b.pixels[i].rgba[c];
                power += x * x;
                error += d * d;
                worst = std::max(worst, std::abs(d));
            }
        std::printf("relative RMSE %.3g  max difference %.3g\n", power > 0 ? std::sqrt(error / power) : std::sqrt(error), worst);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "voxlux_compare: %s\n", e.what());
        return 2;
    }
}
