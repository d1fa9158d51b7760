#include "volume/make_cloud.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace voxlux {
namespace {

float hashToUnit(glm::ivec3 c, uint32_t seed) {
    uint32_t h = uint32_t(c.x) * 0x8da6b343u ^ uint32_t(c.y) * 0xd8163841u ^ uint32_t(c.z) * 0xcb1ab31fu ^ seed * 0x9e3779b9u;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return float(h) / 4294967296.0f;
}

// Value noise with a smooth (C1) fade, in [0, 1).
float valueNoise(glm::vec3 p, uint32_t seed) {
    glm::vec3 f = glm::floor(p);
    glm::ivec3 i(f);
    glm::vec3 t = p - f;
    t = t * t * (3.0f - 2.0f * t);
    float v[8];
    for (int k = 0; k < 8; ++k) v[k] = hashToUnit(i + glm::ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1), seed);
    float x0 = glm::mix(glm::mix(v[0], v[1], t.x), glm::mix(v[2], v[3], t.x), t.y);
    float x1 = glm::mix(glm::mix(v[4], v[5], t.x), glm::mix(v[6], v[7], t.x), t.y);
    return glm::mix(x0, x1, t.z);
}

float fbm(glm::vec3 p, uint32_t seed) {
    float sum = 0.0f, amplitude = 0.5f;
    for (int octave = 0; octave < 5; ++octave) {
        sum += amplitude * valueNoise(p, seed + uint32_t(octave));
        p *= 2.03f;
        amplitude *= 0.5f;
    }
    return sum;  // about [0, 0.97)
}

struct Lump {
    glm::vec3 centre;  // in units of the cloud's half-width
    float radius;
};

// A flat-bottomed cumulus: a wide base and a few towers.
// Radii leave room for the noise to push the surface out without reaching the domain's faces.
constexpr Lump kLumps[] = {
    {{0.0f, -0.2f, 0.0f}, 0.5f}, {{-0.48f, -0.28f, 0.1f}, 0.36f}, {{0.48f, -0.28f, -0.05f}, 0.38f},
    {{-0.1f, 0.2f, 0.05f}, 0.4f}, {{0.25f, 0.1f, 0.15f}, 0.32f}, {{-0.35f, 0.02f, -0.2f}, 0.3f},
};

}  // namespace

openvdb::FloatGrid::Ptr makeCloud(const CloudParams& params) {
    const int n = params.resolution;
    const float voxel = params.world_size / float(n);
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    auto acc = grid->getAccessor();
    const int half = n / 2;
    for (int z = -half; z < half; ++z)
        for (int y = -half; y < half; ++y)
            for (int x = -half; x < half; ++x) {
                glm::vec3 p = (glm::vec3(x, y, z) + 0.5f) / float(half);  // [-1, 1]
                if (p.y < -0.42f) continue;  // flat base
                float shape = -INFINITY;
                for (const auto& l : kLumps) shape = std::max(shape, 1.0f - glm::length(p - l.centre) / l.radius);
                if (shape <= -0.3f) continue;
                float erosion = fbm(p * 4.5f, params.seed) - 0.45f;
                float d = std::clamp((shape + 1.1f * erosion) * 3.0f, 0.0f, 1.0f);
                if (d > 0.0f) acc.setValue(openvdb::Coord(x, y, z), d);
            }
    grid->pruneGrid();
    return grid;
}

}  // namespace voxlux
