#include "optics/transfer_function_2d.h"

#include <algorithm>

namespace voxlux {
namespace {

// How far inside a rectangle the point is, per axis, from 0 at an edge to 1 at the centre.
float rectangleDepth(const TransferRegion& r, glm::vec2 p) {
    const glm::vec2 lo(r.value.x, r.gradient.x), hi(r.value.y, r.gradient.y);
    if (p.x < lo.x || p.x > hi.x || p.y < lo.y || p.y > hi.y) return -1.0f;
    glm::vec2 depth = 2.0f * glm::min(p - lo, hi - p) / (hi - lo);
    // No gradient lies below 0: a range from 0 fades at its upper end only, or the voxels inside
    // a material (gradient 0) would have no weight.
    if (lo.y <= 0.0f) depth.y = std::min(1.0f, 2.0f * (hi.y - p.y) / (hi.y - lo.y));
    return std::min(depth.x, depth.y);
}

// The same for a triangle: 3 times the smallest barycentric coordinate (1 at the centroid).
float triangleDepth(const TransferRegion& r, glm::vec2 p) {
    const glm::vec2 a = r.corners[0], b = r.corners[1], c = r.corners[2];
    const auto cross = [](glm::vec2 u, glm::vec2 v) { return u.x * v.y - u.y * v.x; };
    const float area = cross(b - a, c - a);
    const float wa = cross(b - p, c - p) / area, wb = cross(c - p, a - p) / area, wc = 1.0f - wa - wb;
    const float least = std::min({wa, wb, wc});
    return least < 0.0f ? -1.0f : 3.0f * least;
}

}  // namespace

float regionWeight(const TransferRegion& region, glm::vec2 point) {
    const float depth = region.triangle ? triangleDepth(region, point) : rectangleDepth(region, point);
    if (depth < 0.0f) return 0.0f;
    return region.fade > 0.0f ? std::min(depth / region.fade, 1.0f) : 1.0f;
}

Classified classify2d(const std::vector<TransferRegion>& regions, float value, float gradient) {
    Classified out;
    glm::vec3 albedo_sum(0.0f), depth_sum(0.0f);
    float surface_sum = 0.0f;
    for (const TransferRegion& r : regions) {
        const float sigma = regionWeight(r, {value, gradient}) * r.extinction;
        out.extinction += sigma;
        albedo_sum += sigma * r.albedo;
        if (r.transport) depth_sum -= sigma * glm::log(*r.transport);
        surface_sum += sigma * r.surface.value_or(1.0f);
    }
    if (out.extinction > 0.0f) {
        out.albedo = albedo_sum / out.extinction;
        out.transport = glm::exp(-depth_sum / out.extinction);
        out.surface = surface_sum / out.extinction;
    }
    return out;
}

}  // namespace voxlux
