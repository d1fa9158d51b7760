#include "optics/environment_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/gtc/constants.hpp>

namespace voxlux {

namespace {

constexpr double kPi = glm::pi<double>();

// The index of the interval of a CDF (n + 1 rising values from 0) that `target` falls in, skipping
// intervals of zero width.
size_t intervalOf(const double* cdf, size_t n, double target) {
    const double* upper = std::upper_bound(cdf + 1, cdf + n + 1, target);
    return std::min<size_t>(size_t(upper - cdf) - 1, n - 1);
}

}  // namespace

glm::mat3 environmentFrame(glm::vec3 up, float rotation_degrees) {
    up = glm::normalize(up);
    const glm::vec3 seed = std::abs(up.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 x0 = glm::normalize(seed - up * glm::dot(seed, up));
    const glm::vec3 y0 = glm::cross(up, x0);
    const double r = glm::radians(double(rotation_degrees));
    const glm::vec3 x = float(std::cos(r)) * x0 + float(std::sin(r)) * y0;
    return glm::mat3(x, glm::cross(up, x), up);
}

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<glm::vec3> radiance, glm::vec3 up, float rotation_degrees)
    : width_(width), height_(height), radiance_(std::move(radiance)), frame_(environmentFrame(up, rotation_degrees)) {
    if (width <= 0 || height <= 0 || radiance_.size() != size_t(width) * height)
        throw std::invalid_argument("an environment map needs width x height pixels");
    row_cdf_.assign(size_t(height) + 1, 0.0);
    column_cdf_.assign(size_t(height) * (width + 1), 0.0);
    for (int y = 0; y < height; ++y) {
        double* row = &column_cdf_[size_t(y) * (width + 1)];
        const double solid_angle = pixelSolidAngle(y);
        for (int x = 0; x < width; ++x) row[x + 1] = row[x] + double(environmentLuminance(at({x, y}))) * solid_angle;
        row_cdf_[size_t(y) + 1] = row_cdf_[size_t(y)] + row[width];
    }
    total_ = row_cdf_.back();
}

glm::vec3 EnvironmentMap::direction(glm::vec2 uv) const {
    const double phi = kPi * (1.0 - 2.0 * uv.x), theta = kPi * uv.y;
    const glm::vec3 local(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)));
    return frame_ * local;
}

glm::vec3 EnvironmentMap::pixelDirection(int x, int y) const {
    return direction({(float(x) + 0.5f) / float(width_), (float(y) + 0.5f) / float(height_)});
}

glm::ivec2 EnvironmentMap::pixelOf(glm::vec3 direction) const {
    const glm::vec3 local = glm::transpose(frame_) * direction;
    const double u = 0.5 - std::atan2(double(local.y), double(local.x)) / (2.0 * kPi);
    const double v = std::acos(std::clamp(double(local.z), -1.0, 1.0)) / kPi;
    return {std::clamp(int(u * width_), 0, width_ - 1), std::clamp(int(v * height_), 0, height_ - 1)};
}

glm::vec3 EnvironmentMap::filtered(glm::vec3 direction) const {
    const glm::vec3 local = glm::transpose(frame_) * direction;
    const double u = 0.5 - std::atan2(double(local.y), double(local.x)) / (2.0 * kPi);
    const double v = std::acos(std::clamp(double(local.z), -1.0, 1.0)) / kPi;
    const double fx = u * width_ - 0.5, fy = std::clamp(v * height_ - 0.5, 0.0, double(height_ - 1));
    const int x0 = int(std::floor(fx)), y0 = int(fy), y1 = std::min(y0 + 1, height_ - 1);
    const float ax = float(fx - x0), ay = float(fy - y0);
    const auto column = [&](int x) { return ((x % width_) + width_) % width_; };
    const glm::vec3 top = glm::mix(at({column(x0), y0}), at({column(x0 + 1), y0}), ax);
    const glm::vec3 bottom = glm::mix(at({column(x0), y1}), at({column(x0 + 1), y1}), ax);
    return glm::mix(top, bottom, ay);
}

double EnvironmentMap::pixelSolidAngle(int y) const {
    return 2.0 * kPi / width_ * (std::cos(kPi * y / height_) - std::cos(kPi * (y + 1) / height_));
}

glm::dvec3 EnvironmentMap::power() const {
    glm::dvec3 sum(0.0);
    for (int y = 0; y < height_; ++y) {
        glm::dvec3 row(0.0);
        for (int x = 0; x < width_; ++x) row += glm::dvec3(at({x, y}));
        sum += row * pixelSolidAngle(y);
    }
    return sum;
}

glm::vec3 EnvironmentMap::sample(glm::vec2 u, float& pdf) const {
    if (!(total_ > 0.0)) {
        pdf = 0.0f;
        return frame_[2];
    }
    // The row by its share, then the column within it; the point uniform in solid angle over the
    // pixel (cos theta uniform between the row's edges), so the density is constant across it.
    const size_t y = intervalOf(row_cdf_.data(), size_t(height_), double(u.y) * total_);
    const double* row = &column_cdf_[y * (width_ + 1)];
    const double in_row = double(u.x) * row[width_];
    const size_t x = intervalOf(row, size_t(width_), in_row);
    const double across = std::clamp((in_row - row[x]) / std::max(row[x + 1] - row[x], 1e-300), 0.0, 1.0);
    const double down = std::clamp((double(u.y) * total_ - row_cdf_[y]) / std::max(row_cdf_[y + 1] - row_cdf_[y], 1e-300), 0.0, 1.0);
    const double cos_top = std::cos(kPi * double(y) / height_), cos_bottom = std::cos(kPi * double(y + 1) / height_);
    const double theta = std::acos(std::clamp(cos_top + (cos_bottom - cos_top) * down, -1.0, 1.0));
    const glm::vec3 dir = direction({float((double(x) + across) / width_), float(theta / kPi)});
    pdf = this->pdf(dir);
    return dir;
}

float EnvironmentMap::pdf(glm::vec3 direction) const {
    if (!(total_ > 0.0)) return 0.0f;
    // The pixel's share (luminance x solid angle / total) over its solid angle.
    return float(double(environmentLuminance(lookup(direction))) / total_);
}

}  // namespace voxlux
