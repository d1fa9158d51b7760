// Preview stage output: display-referred RGB(A) as an 8-bit sRGB PNG, for review tools and web
// pages that have no OpenEXR or OpenColorIO.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace voxlux {

struct PngWriteReport {
    size_t non_finite = 0;  // samples that were NaN/Inf and written as 0
    size_t clipped = 0;     // finite samples outside [0, 1], clamped
};

// One display-referred channel as the PNG stores it: clamped to [0, 1] and rounded (as std::lround;
// adding 0.5 in double is exact), a non-finite value 0. The viewer's texture uses it too.
inline uint8_t displayByte(float v) {
    return uint8_t(double((std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f) * 255.0f) + 0.5);
}

// Writes display-referred RGB (already encoded for the display, e.g. by an OCIO view) as an 8-bit
// sRGB-tagged PNG via a temporary file renamed into place (writeAtomically from exr_writer.h).
// Values are clamped to [0,1] and rounded; non-finite values become 0 and are counted. PNG alpha
// is straight, so with `with_alpha` the colour must not be premultiplied. `rgba` is row-major,
// row 0 at the top. Throws InputError "<path>: cannot write (...)" and leaves no file on failure.
PngWriteReport writePng(const std::string& path, int width, int height, const std::vector<glm::vec4>& rgba,
                        bool with_alpha);

}  // namespace voxlux
