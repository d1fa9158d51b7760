// An environment light's map: the radiance arriving from every direction, as a lat-long
// (equirectangular) image, oriented in the world, and a piecewise-constant distribution over its
// pixels for importance sampling (pbrt's marginal/conditional CDFs, each pixel weighted by its
// luminance times its solid angle). Costs 4 floats a pixel for the CDFs beside the 3 of radiance;
// a lookup or a sample is a binary search over a row and a column.
//
// Orientation, as Blender's equirectangular mapping with z up: the top row faces `up`, the bottom
// row the opposite; the image's centre column faces the frame's x, its left quarter the frame's y
// (u = 1/2 - atan2(y, x) / 2 pi, v = theta / pi from the top). The frame's x and y are the world's
// x, and up x x; `rotation` turns them about up, counter-clockwise seen from above.
#pragma once
#include <vector>

#include <glm/glm.hpp>

namespace voxlux {

// The map's frame around `up` (any length): x the world's x made perpendicular to up (the world's y
// when up lies along x), turned about up by `rotation_degrees`; y = up x x. Columns x, y, up.
glm::mat3 environmentFrame(glm::vec3 up, float rotation_degrees);

class EnvironmentMap {
public:
    // `radiance`: width x height pixels, row 0 at the top; `up` the world direction of the top
    // row (any length), `rotation_degrees` about it. Throws std::invalid_argument on an empty map.
    EnvironmentMap(int width, int height, std::vector<glm::vec3> radiance, glm::vec3 up, float rotation_degrees);

    int width() const { return width_; }
    int height() const { return height_; }
    const std::vector<glm::vec3>& radiance() const { return radiance_; }
    // Columns: the map's x (the centre column's azimuth), y, and up; orthonormal, right-handed.
    const glm::mat3& frame() const { return frame_; }

    // The world direction of image point (u, v), u across and v down, both in [0, 1].
    glm::vec3 direction(glm::vec2 uv) const;
    glm::vec3 pixelDirection(int x, int y) const;   // of a pixel's centre
    // The pixel a unit world direction falls in.
    glm::ivec2 pixelOf(glm::vec3 direction) const;
    glm::vec3 lookup(glm::vec3 direction) const { return at(pixelOf(direction)); }
    // Bilinear between pixel centres (wrapping across the seam): the map as a camera sees it. The
    // lighting reads lookup(), the piecewise-constant map its sampling draws from.
    glm::vec3 filtered(glm::vec3 direction) const;
    glm::vec3 at(glm::ivec2 pixel) const { return radiance_[size_t(pixel.y) * width_ + pixel.x]; }
    // Solid angle of any pixel of row y: 2 pi / width * (cos theta_top - cos theta_bottom).
    double pixelSolidAngle(int y) const;
    // Integral of the radiance over the sphere (the irradiance the whole map carries, summed over
    // directions: for a constant map L, 4 pi L).
    glm::dvec3 power() const;

    // A direction drawn with probability proportional to luminance times solid angle, from two
    // uniform numbers; `pdf` its density per steradian (0 only for an all-black map, which
    // returns up).
    glm::vec3 sample(glm::vec2 u, float& pdf) const;
    // The density sample() draws `direction` with, per steradian.
    float pdf(glm::vec3 direction) const;

private:
    int width_, height_;
    std::vector<glm::vec3> radiance_;
    glm::mat3 frame_;
    // Row CDF (height + 1) and each row's column CDF (height x (width + 1)), unnormalised sums of
    // luminance x solid angle; total_ their sum.
    std::vector<double> row_cdf_, column_cdf_;
    double total_ = 0.0;
};

// Luminance of linear Rec.709 RGB: what the sampling and the median cut weigh pixels by.
inline float environmentLuminance(glm::vec3 rgb) { return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z; }

}  // namespace voxlux
