// The comparison of the GL and CPU backends (gl_agreement.h).
#include "backend/gl/gl_agreement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "backend/backend_choice.h"
#include "render/renderer.h"
#include "scene/camera.h"
#include "test_support.h"

namespace voxlux::test::gl_agreement {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

// A box of constant density (crossing the origin, so brick coordinates go negative) beside a
// sphere of smooth noise, on a 0.1-unit grid.
constexpr int kSphereRadius = 12;
const Coord kSphereCentre(22, 4, 8);

float noise(const Coord& c) {
    return 0.5f + 0.5f * std::sin(0.7f * float(c.x())) * std::sin(0.9f * float(c.y()) + 1.0f) *
                      std::cos(0.8f * float(c.z()));
}

// Calls f(coord, r) for every voxel of the sphere, r = distance from the centre / radius.
template <typename F>
void forSphere(F f) {
    const Coord r(kSphereRadius);
    for (auto it = CoordBBox(kSphereCentre - r, kSphereCentre + r).begin(); it; ++it) {
        const Coord d = *it - kSphereCentre;
        float dist = std::sqrt(float(d.x() * d.x() + d.y() * d.y() + d.z() * d.z())) / float(kSphereRadius);
        if (dist <= 1.0f) f(*it, dist);
    }
}

}  // namespace

LoadedVolume makeVolume(bool emission_and_color) {
    auto density = boxGrid(Coord(-16, -8, -4), Coord(7, 15, 19), 1.0f, 0.1);
    auto acc = density->getAccessor();
    forSphere([&](const Coord& c, float r) { acc.setValue(c, 2.0f * noise(c) * (1.0f - r)); });
    if (!emission_and_color) return volumeFromGrid(density);
    auto emission = openvdb::FloatGrid::create(0.0f);
    auto color = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.0f));
    emission->setTransform(density->transform().copy());
    color->setTransform(density->transform().copy());
    auto eacc = emission->getAccessor();
    auto cacc = color->getAccessor();
    forSphere([&](const Coord& c, float r) {
        eacc.setValue(c, std::max(0.0f, 1.0f - 2.0f * r) * noise(c + Coord(5)));
        cacc.setValue(c, openvdb::Vec3s(1.0f - r, noise(c), r));
    });
    return volumeFromGrid(density, {emission}, color);
}

openvdb::FloatGrid::Ptr flameGrid() {
    auto g = boxGrid(Coord(-16, -8, -4), Coord(-5, 15, 19), 0.0f, 0.1);
    g->setName("flame");
    for (auto it = g->beginValueOn(); it; ++it) it.setValue(noise(it.getCoord() + Coord(11)));
    return g;
}

EmissionSource emissionSource() {
    EmissionSource e;
    e.color = glm::vec3(1.0f, 0.5f, 0.2f);
    e.intensity = 4.0f;
    return e;
}

Light directionalLight() {
    Light l;
    l.type = LightType::Directional;
    l.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, -0.3f));
    l.color = glm::vec3(1.0f, 0.95f, 0.9f);
    l.intensity = 3.0f;
    return l;
}

Light pointLight() {
    Light l;
    l.type = LightType::Point;
    l.position = glm::vec3(1.2f, 1.0f, 1.0f);   // just inside the sphere's edge, facing the box
    l.color = glm::vec3(0.6f, 0.8f, 1.0f);
    l.intensity = 2.0f;
    return l;
}

Light spotLight() {
    Light l;
    l.type = LightType::Spot;
    l.position = glm::vec3(-3.0f, 3.0f, 4.0f);
    l.direction = glm::normalize(glm::vec3(0.6f, -0.5f, -0.5f));
    l.intensity = 40.0f;
    l.cone_angle = 20.0f;
    l.cone_softness = 8.0f;
    return l;
}

Scene baseScene() {
    Scene s;
    s.render.width = 74;    // not a multiple of the 8x8 work group
    s.render.height = 66;   // more rows than one GL dispatch band (64)
    s.volume().material.density_scale = 2.0f;   // extinction per world unit: the box is ~5 optical depths deep
    s.volume().material.anisotropy = 0.3f;
    s.effects.shadows = ShadowMethod::Raymarch;
    s.lights = {directionalLight(), pointLight()};
    return s;
}

Renders renderBoth(LoadedVolume volume, Scene scene, KernelBackend& gl) {
    const CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    glm::vec3 lo, hi;
    worldBounds(volume.index_to_world, glm::vec3(box.min().x(), box.min().y(), box.min().z()),
                glm::vec3(box.max().x() + 1, box.max().y() + 1, box.max().z() + 1), lo, hi);
    Camera camera = frameBox(lo, hi, 40.0f, float(scene.render.width) / float(scene.render.height));
    camera.position = glm::mix(camera.look_at, camera.position, 0.45f);
    scene.camera = camera;
    auto cpu = makeCpuBackend();
    return {Renderer(scene, volume, *cpu).render(std::nullopt, false).image,
            Renderer(scene, volume, gl).render(std::nullopt, false).image};
}

namespace {

float component(const kernel::VxPixel& p, int i) { return reinterpret_cast<const float*>(&p)[i]; }

ChannelStats compare(const RenderImage& cpu, const RenderImage& gl, const Channel& ch) {
    ChannelStats s;
    double sum_sq = 0.0, sum_ref = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) {
        if (cpu.pixels[i].rgba.w < ch.min_alpha) continue;
        for (int k = ch.first; k < ch.first + ch.count; ++k, ++n) {
            const double ref = component(cpu.pixels[i], k), d = component(gl.pixels[i], k) - ref;
            sum_sq += d * d;
            sum_ref += std::abs(ref);
            s.max_abs = std::max(s.max_abs, std::abs(d));
            s.peak = std::max(s.peak, std::abs(ref));
        }
    }
    s.rmse = n ? std::sqrt(sum_sq / double(n)) : 0.0;
    s.mean = n ? sum_ref / double(n) : 0.0;
    return s;
}

}  // namespace

std::array<ChannelStats, kChannelCount> expectMatch(const Renders& r) {
    std::array<ChannelStats, kChannelCount> stats;
    EXPECT_EQ(r.gl.width, r.cpu.width);
    EXPECT_EQ(r.gl.height, r.cpu.height);
    if (r.gl.pixels.size() != r.cpu.pixels.size()) {
        ADD_FAILURE() << "GL image has " << r.gl.pixels.size() << " pixels, CPU " << r.cpu.pixels.size();
        return stats;
    }
    for (int c = 0; c < kChannelCount; ++c) {
        const ChannelStats& s = stats[c] = compare(r.cpu, r.gl, kChannels[c]);
        EXPECT_LE(s.rmse, kRmseOfMean * s.mean) << kChannels[c].name << ": mean |cpu| " << s.mean;
        EXPECT_LE(s.max_abs, kMaxAbsOfPeak * s.peak) << kChannels[c].name << ": peak |cpu| " << s.peak;
        // The measured agreement, which docs/architecture.md quotes.
        std::printf("  %-13s rmse/mean %.2g  max/peak %.2g\n", kChannels[c].name, s.mean > 0 ? s.rmse / s.mean : 0.0,
                    s.peak > 0 ? s.max_abs / s.peak : 0.0);
    }
    // Not vacuous: the volume is in view and partly opaque.
    EXPECT_GT(stats[kRgba].peak, 0.5);
    return stats;
}


}  // namespace voxlux::test::gl_agreement
