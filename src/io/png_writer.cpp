#include "io/png_writer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <png.h>

#include "io/exr_writer.h"

namespace voxlux {

PngWriteReport writePng(const std::string& path, int width, int height, const std::vector<glm::vec4>& rgba,
                        bool with_alpha) {
    if (rgba.size() != size_t(width) * size_t(height))
        throw std::invalid_argument("writePng: " + std::to_string(rgba.size()) + " pixels for a " +
                                    std::to_string(width) + "x" + std::to_string(height) + " image");
    const int channels = with_alpha ? 4 : 3;
    PngWriteReport report;
    std::vector<png_byte> bytes(rgba.size() * channels);
    for (size_t i = 0; i < rgba.size(); ++i)
        for (int k = 0; k < channels; ++k) {
            const float v = rgba[i][k];
            if (!std::isfinite(v)) ++report.non_finite;
            else if (v < 0.0f || v > 1.0f) ++report.clipped;
            bytes[i * channels + k] = displayByte(v);
        }

    // libpng's simplified API: errors come back as a message instead of a longjmp, and it tags
    // 8-bit colour as sRGB (an sRGB chunk) since PNG_IMAGE_FLAG_COLORSPACE_NOT_sRGB is not set.
    writeAtomically(path, [&](const std::string& tmp) {
        png_image image{};
        image.version = PNG_IMAGE_VERSION;
        image.width = png_uint_32(width);
        image.height = png_uint_32(height);
        image.format = with_alpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
        if (!png_image_write_to_file(&image, tmp.c_str(), 0, bytes.data(), 0, nullptr))
            throw std::runtime_error(image.message);
    });
    return report;
}

}  // namespace voxlux
