#include "viewer/orbit_camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/camera.h"

namespace voxlux {

Camera lookAtForm(const Camera& camera, glm::vec3 pivot) {
    if (!camera.matrix) return camera;
    const glm::mat4 m = *camera.matrix;
    Camera c = camera;
    c.matrix.reset();
    c.position = glm::vec3(m[3]);
    c.look_at = c.position - glm::normalize(glm::vec3(m[2])) * std::max(glm::length(pivot - c.position), 1e-3f);
    c.up = glm::normalize(glm::vec3(m[1]));
    return c;
}

Camera orbit(const Camera& camera, float yaw, float pitch) {
    Camera c = camera;
    const glm::vec3 up = glm::normalize(c.up);
    glm::vec3 offset = c.position - c.look_at;
    offset = glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(yaw), up) * glm::vec4(offset, 0.0f));
    // Limit the pitch so the camera never looks straight along up, where its frame flips.
    const float length = glm::length(offset);
    const float elevation = glm::degrees(std::asin(std::clamp(glm::dot(offset / length, up), -1.0f, 1.0f)));
    const float turned = std::clamp(elevation + pitch, -89.0f, 89.0f) - elevation;
    const glm::vec3 right = glm::normalize(glm::cross(up, offset));
    offset = glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(-turned), right) * glm::vec4(offset, 0.0f));
    c.position = c.look_at + offset;
    return c;
}

Camera pan(const Camera& camera, glm::vec2 offset) {
    Camera c = camera;
    const glm::mat4 frame = cameraToWorld(c);
    const float height = 2.0f * glm::length(c.position - c.look_at) * std::tan(glm::radians(c.fov) * 0.5f);
    const glm::vec3 move = (glm::vec3(frame[0]) * offset.x + glm::vec3(frame[1]) * offset.y) * height;
    c.position += move;
    c.look_at += move;
    return c;
}

Camera dolly(const Camera& camera, float factor) {
    Camera c = camera;
    c.position = c.look_at + (c.position - c.look_at) * std::max(factor, 1e-3f);
    return c;
}

Camera frameAlong(const Camera& camera, glm::vec3 lo, glm::vec3 hi) {
    Camera c = camera;
    const glm::vec3 centre = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-6f);
    const float distance = radius / std::sin(glm::radians(c.fov) * 0.5f);
    glm::vec3 dir = c.position - c.look_at;
    dir = glm::length(dir) > 0.0f ? glm::normalize(dir) : glm::vec3(0, 0, 1);
    c.look_at = centre;
    c.position = centre + dir * distance;
    return c;
}

bool projectToImage(const Camera& camera, glm::vec2 size, glm::vec3 p, glm::vec2& pixel) {
    const glm::vec4 view = glm::inverse(cameraToWorld(camera)) * glm::vec4(p, 1.0f);
    if (view.z >= 0.0f) return false;   // behind the camera (it looks down -Z)
    const glm::vec4 clip = cameraProjection(camera, size.x / size.y) * view;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    pixel = glm::vec2((ndc.x * 0.5f + 0.5f) * size.x, (0.5f - ndc.y * 0.5f) * size.y);
    return true;
}

}  // namespace voxlux
