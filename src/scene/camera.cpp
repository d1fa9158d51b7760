#include "scene/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace voxlux {

glm::mat4 cameraToWorld(const Camera& c) {
    if (c.matrix) return *c.matrix;
    return glm::inverse(glm::lookAt(c.position, c.look_at, c.up));
}

float lensRadius(const Camera& c) {
    if (!(c.fstop > 0.0f)) return 0.0f;
    // The focal length of the frame's height: the camera's own, or its field of view's.
    const float focal_mm = c.film_back.y / (2.0f * std::tan(glm::radians(c.fov) * 0.5f));
    return focal_mm / (2.0f * c.fstop) / c.world_unit_mm;
}

glm::mat4 cameraProjection(const Camera& c, float aspect) {
    return glm::perspective(glm::radians(c.fov), aspect, 0.01f, 1e5f);
}

void worldBounds(const glm::mat4& m, glm::vec3 lo, glm::vec3 hi, glm::vec3& out_lo, glm::vec3& out_hi) {
    out_lo = glm::vec3(INFINITY);
    out_hi = glm::vec3(-INFINITY);
    for (int i = 0; i < 8; ++i) {
        glm::vec3 corner(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
        glm::vec3 w = glm::vec3(m * glm::vec4(corner, 1.0f));
        out_lo = glm::min(out_lo, w);
        out_hi = glm::max(out_hi, w);
    }
}

Camera frameBox(glm::vec3 lo, glm::vec3 hi, float fov, float aspect, const glm::mat3& frame) {
    Camera c;
    c.fov = fov;
    c.look_at = 0.5f * (lo + hi);
    float radius = 0.5f * glm::length(hi - lo);
    // Distance at which the bounding sphere fits the narrower of the two fields of view.
    float half = glm::radians(fov) * 0.5f;
    float half_narrow = std::atan(std::tan(half) * std::min(1.0f, aspect));
    float distance = radius / std::sin(half_narrow) * 1.05f;
    c.up = frame[1];
    c.position = c.look_at + frame * glm::normalize(glm::vec3(0.55f, 0.3f, 1.0f)) * distance;
    return c;
}

Light defaultKeyLight(const glm::mat3& frame) {
    Light l;
    l.type = LightType::Directional;
    l.direction = frame * glm::normalize(glm::vec3(1.0f, -0.6f, -0.4f));
    l.color = glm::vec3(1.0f);
    l.intensity = 10.0f;  // with the 1/(4 pi) phase, about 0.7 of radiance off an unshadowed albedo-0.9 medium
    return l;
}

}  // namespace voxlux
