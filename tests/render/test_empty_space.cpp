// Empty space between parts of a volume (shaders/vx_dda.h): the CPU march steps over regions that
// hold no brick in one step, and what it renders is what each part renders alone, composited.
// Two boxes 2000 voxels apart along the view, with 31 empty regions between them. GL keeps the
// brick walk (vx_skips_regions in shaders/vx_dda.h) and is held to the same composite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "backend/backend_choice.h"
#include "kernel/cpu_kernel.h"
#include "render/renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr float kSigma = 0.05f;
const openvdb::Coord kNearLo(0, 0, 0), kNearHi(15, 15, 15);          // the part the camera sees first
const openvdb::Coord kFarLo(0, 0, -2000), kFarHi(15, 15, -1985);     // 2000 voxels further down -z

openvdb::FloatGrid::Ptr parts(bool near, bool far) {
    auto g = boxGrid({0, 0, 0}, {-1, -1, -1}, 0.0f);
    if (near) g->denseFill(openvdb::CoordBBox(kNearLo, kNearHi), kSigma, true);
    if (far) g->denseFill(openvdb::CoordBBox(kFarLo, kFarHi), kSigma, true);
    return g;
}

// 16 x 16 pixels looking down -z at both parts, lit from the side (+x) by a directional light.
Scene sideLit(ShadowMethod shadows) {
    Scene s;
    s.render.width = 16;
    s.render.height = 16;
    s.render.step = 0.5f;
    s.effects.shadows = shadows;
    Light l;
    l.direction = glm::vec3(-1.0f, 0.0f, 0.0f);
    l.intensity = 3.0f;
    s.lights = {l};
    return s;
}

// Far above both parts and narrow, so both fill most of the image; the samples (at (k + 0.5)
// steps from the camera) never fall on a voxel plane.
Camera overhead() {
    Camera c;
    c.position = glm::vec3(8.0f, 8.0f, 20016.1f);
    c.look_at = glm::vec3(8.0f, 8.0f, 0.0f);
    c.fov = 0.06f;
    return c;
}

RenderImage render(bool near, bool far, const Scene& scene, KernelBackend& backend) {
    auto prepared = prepare(volumeFromGrid(parts(near, far)), scene, overhead());
    return backend.march(prepared->inputs);
}

// Light from the side reaches each part without crossing the other, so the two parts together
// are the near part over the far one: rgb = near + T_near * far, T = T_near * T_far.
TEST(EmptySpace, TwoPartsFarApartRenderAsEachAloneComposited) {
    std::vector<std::unique_ptr<KernelBackend>> backends;
    backends.push_back(makeCpuBackend());
    if (auto gl = glBackendOrSkip()) backends.push_back(std::move(gl));
    for (auto& backend : backends) {
        for (ShadowMethod shadows : {ShadowMethod::None, ShadowMethod::Raymarch}) {
            // GL's shadow rays run the same walk as its camera rays; llvmpipe takes minutes on them.
            if (backend->device() == Device::Gl && shadows == ShadowMethod::Raymarch) continue;
            SCOPED_TRACE(backend->name() + (shadows == ShadowMethod::None ? ", no shadows" : ", ray-marched shadows"));
            const Scene scene = sideLit(shadows);
            const RenderImage both = render(true, true, scene, *backend);
            const RenderImage near = render(true, false, scene, *backend);
            const RenderImage far = render(false, true, scene, *backend);
            double worst = 0.0, far_light = 0.0;
            for (size_t i = 0; i < both.pixels.size(); ++i) {
                const kernel::VxPixel &b = both.pixels[i], &n = near.pixels[i], &f = far.pixels[i];
                for (int c = 0; c < 3; ++c) {
                    const double expected = n.rgba[c] + double(n.transmittance) * f.rgba[c];
                    worst = std::max(worst, std::abs(b.rgba[c] - expected) / std::max(expected, 1e-3));
                }
                EXPECT_NEAR(b.transmittance, n.transmittance * f.transmittance, 1e-6) << "pixel " << i;
                EXPECT_NEAR(b.samples, n.samples + f.samples, 2.0f) << "pixel " << i;
                far_light += f.rgba.x;
            }
            EXPECT_GT(far_light, 1.0) << "the far part is seen and lit";
            EXPECT_LT(worst, 1e-5);
            std::printf("  %s: largest relative difference %.2g\n", backend->name().c_str(), worst);
        }
    }
}

// A shadow ray up through both parts (across the empty regions between them) sees the optical
// depth of both: its transmittance is the product of each part's alone.
TEST(EmptySpace, ShadowRayAcrossTheGapSeesBothParts) {
    const auto transmittance = [](bool near, bool far) {
        auto prepared = prepare(volumeFromGrid(parts(near, far)), sideLit(ShadowMethod::Raymarch), overhead());
        kernel::CpuKernel k = bindCpuKernel(prepared->inputs);
        return k.vx_shadow_transmittance(glm::vec3(7.3f, 8.6f, -2100.0f), glm::vec3(0, 0, 1), 1e30f, VX_ALL_LINKS);
    };
    const float near = transmittance(true, false), far = transmittance(false, true), both = transmittance(true, true);
    const float one_part = std::exp(-kSigma * 16.0f);   // 16 voxels of kSigma each (T in world units of 1 voxel)
    EXPECT_NEAR(near, one_part, 1e-3f);
    EXPECT_NEAR(far, one_part, 1e-3f);
    EXPECT_NEAR(both, near * far, 1e-6f);
}

}  // namespace
}  // namespace voxlux::test
