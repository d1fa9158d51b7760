// Many lights in one illumination volume (Sunden 2015): which passes carry a light, point lights
// inside the volume against the analytic answer, additivity, selective updates against
// from-scratch volumes after many random edits on both backends, toggling, HDR extremes, the
// LightRig API and `render --light-edit`.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "backend/backend_choice.h"
#include "lighting/propagation/kernel/cpu_propagation_kernel.h"
#include "lighting/propagation/cpu_propagation.h"
#include "core/error.h"
#include "lighting/propagation/propagation_stages.h"
#include "render/light_rig.h"
#include "lighting/propagation/light_sweeps.h"
#include "render/renderer.h"
#include "lighting/propagation/illumination_cells.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

bool hasSweep(const std::vector<Sweep>& sweeps, int axis, int sign) {
    for (const Sweep& s : sweeps)
        if (s.axis == axis && s.sign == sign) return true;
    return false;
}

// Directional lights go to the face they travel most towards; ties (face and body diagonals) go
// to z, then y; with blending the second closest face takes Sunden's Eq. 5b share.
TEST(LightSweeps, DirectionalLightsGoToTheExpectedFaces) {
    auto one = sweepsFor({0.2f, -1.0f, 0.1f}, false);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0].axis, 1);
    EXPECT_EQ(one[0].sign, -1);
    auto diagonal = sweepsFor({1.0f, -1.0f, 0.0f}, false);
    ASSERT_EQ(diagonal.size(), 1u);
    EXPECT_EQ(diagonal[0].axis, 1);   // x and y tie: y
    auto body = sweepsFor({-1.0f, 1.0f, -1.0f}, true);
    ASSERT_EQ(body.size(), 2u);
    EXPECT_EQ(body[0].axis, 2);
    EXPECT_EQ(body[0].sign, -1);
    EXPECT_EQ(body[1].axis, 1);
    EXPECT_EQ(body[1].sign, 1);
    EXPECT_FLOAT_EQ(body[0].weight, 0.5f);
    // In the plane of two axes the split is Eq. 5a/5b: alpha = 1 - 2 theta / pi.
    for (float deg : {10.0f, 25.0f, 40.0f, 44.0f}) {
        const float t = glm::radians(deg);
        auto s = sweepsFor({std::sin(t), 0.0f, std::cos(t)}, true);
        ASSERT_EQ(s.size(), 2u) << deg;
        EXPECT_EQ(s[0].axis, 2);
        EXPECT_NEAR(s[0].weight, 1.0f - 2.0f * t / float(M_PI), 1e-5f) << deg;
        EXPECT_NEAR(s[1].weight, 2.0f * t / float(M_PI), 1e-5f) << deg;
    }
}

// Point lights: far away one pass, beside or on a face of the volume five, inside all six.
TEST(LightSweeps, PointLightsGoToEveryFaceTheirCellsSee) {
    const glm::ivec3 dims(20, 16, 12);
    const auto far_above = pointLightSweeps({10, 1000, 6}, dims, false);
    ASSERT_EQ(far_above.size(), 1u);
    EXPECT_TRUE(hasSweep(far_above, 1, -1));
    const auto far_corner = pointLightSweeps({-500, -500, 6}, dims, false);   // on the xy diagonal: x and y
    EXPECT_EQ(far_corner.size(), 2u);
    EXPECT_TRUE(hasSweep(far_corner, 0, 1));
    EXPECT_TRUE(hasSweep(far_corner, 1, 1));
    const auto on_face = pointLightSweeps({10, 16, 6}, dims, false);   // centre of the top face
    EXPECT_EQ(on_face.size(), 5u);
    EXPECT_FALSE(hasSweep(on_face, 1, 1));
    const auto beside = pointLightSweeps({-1, 8, 6}, dims, false);
    EXPECT_EQ(beside.size(), 5u);
    EXPECT_FALSE(hasSweep(beside, 0, -1));
    for (glm::vec3 inside : {glm::vec3(10, 8, 6), glm::vec3(3.3f, 12.1f, 1.7f)})
        EXPECT_EQ(pointLightSweeps(inside, dims, false).size(), 6u);
}

// A spot inside the volume needs only the passes its cone reaches (Sunden 2015, Sec. 7.3).
TEST(LightSweeps, SpotLightsInsideNeedOnlyThePassesTheirConeReaches) {
    const glm::ivec3 dims(20, 16, 12);
    const auto all = pointLightSweeps({10, 8, 6}, dims, false);
    ASSERT_EQ(all.size(), 6u);
    const glm::mat3 identity(1.0f);
    const auto down = spotLightSweeps(all, {0, -1, 0}, std::cos(glm::radians(35.0f)), identity);
    ASSERT_EQ(down.size(), 1u);
    EXPECT_EQ(down[0].axis, 1);
    EXPECT_EQ(down[0].sign, -1);
    EXPECT_EQ(spotLightSweeps(all, {0, -1, 0}, std::cos(glm::radians(80.0f)), identity).size(), 5u);
    EXPECT_EQ(spotLightSweeps(all, {1, -1, 0}, std::cos(glm::radians(10.0f)), identity).size(), 2u);   // on the x/y edge
    // A stretched grid (cells twice as long in x): a 40 deg cone along x reaches y and z too.
    const glm::mat3 stretched(glm::vec3(0.5f, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1));
    EXPECT_EQ(spotLightSweeps(all, {1, 0, 0}, std::cos(glm::radians(40.0f)), stretched).size(), 5u);
}

// Every cell's flow is carried in full: the weights of the six sweeps sum to 1, with and without
// blending, including flows on diagonals and along axes.
TEST(LightSweeps, PerCellWeightsSumToOne) {
    kernel::CpuPropagationKernel k;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<glm::vec3> flows = {{1, 0, 0}, {0, -1, 0}, {1, 1, 0}, {-1, 1, 1}, {0, 1e-6f, 1}, {3, 0.01f, 0.2f}};
    for (int n = 0; n < 2000; ++n) flows.push_back({u(rng), u(rng), u(rng)});
    for (bool blend : {false, true})
        for (glm::vec3 f : flows) {
            float sum = 0.0f;
            for (int axis = 0; axis < 3; ++axis)
                for (int sign : {-1, 1}) {
                    const float w = k.vx_sweep_weight(f, axis, sign, blend);
                    EXPECT_GE(w, 0.0f);
                    sum += w;
                }
            ASSERT_NEAR(sum, 1.0f, 1e-6f) << f.x << " " << f.y << " " << f.z << (blend ? " blended" : "");
        }
}

// A homogeneous cube (voxel 1, one cell per voxel) with a point light at a cell centre inside it.
constexpr int kCube = 24;
constexpr int kCubeGrid = kCube + 8;   // the occupied bricks reach one brick below the cube

Scene cubeScene(std::vector<Light> lights, bool indirect) {
    Scene s;
    s.volume().path = "cube";
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.light_resolution = kCubeGrid;
    if (indirect) s.effects.indirect = Indirect{};
    s.lights = std::move(lights);
    return s;
}

Light coloredPointLight(glm::vec3 at, glm::vec3 color, float intensity) {
    Light l;
    l.type = LightType::Point;
    l.position = at;
    l.color = color;
    l.intensity = intensity;
    return l;
}

Light coloredDirectionalLight(glm::vec3 dir, glm::vec3 color, float intensity) {
    Light l;
    l.direction = glm::normalize(dir);
    l.color = color;
    l.intensity = intensity;
    return l;
}

const float* directAt(const IlluminationVolume& v, glm::ivec3 c) {
    return &v.values[((size_t(c.z) * v.dims.y + c.y) * v.dims.x + c.x) * 3];
}

// Inside the medium a point light's direct light is I exp(-sigma r) / r^2. With a light on a cell
// centre, every step along the axes and the face and body diagonals lands on cell centres, so the
// sweeps give it to float precision. Elsewhere each bilinear read mixes a ray's transmittance with
// its neighbours', whose paths differ, so the optical depth is off by a share of itself plus a
// near-field part: under 0.07 sigma r + 0.7 sigma (measured: within 0.07 sigma r on a centre,
// 0.45 sigma beyond it between centres, mostly within 4 cells of the light). In a near-vacuum (sigma 1e-6) only the geometry is left: the inverse-square falloff, the sweeps'
// weights and the first slices past a light between centres (closer than a cell, so their
// neighbours are steep and must still be swept) must be exact everywhere.
void expectPointLightInsideCube(KernelBackend& backend) {
    const float intensity = 50.0f;
    for (float sigma : {1e-6f, 0.1f}) {
        auto grid = boxGrid({0, 0, 0}, {kCube - 1, kCube - 1, kCube - 1}, sigma);
        for (glm::vec3 at : {glm::vec3(12.0f), glm::vec3(11.7f, 12.2f, 12.45f)}) {
            auto lit = illuminate(grid, cubeScene({coloredPointLight(at, glm::vec3(1.0f), intensity)}, false), backend, Camera{});
            const IlluminationVolume& v = lit->volume();
            const bool centred = at == glm::vec3(12.0f);
            float exact_cells = 0.0f;   // relative error where the answer is exact
            float excess = 0.0f;        // optical-depth error beyond 0.07 sigma r, per sigma
            for (int z = 0; z < v.dims.z; ++z)
                for (int y = 0; y < v.dims.y; ++y)
                    for (int x = 0; x < v.dims.x; ++x) {
                        const glm::vec3 p = cellCentre(v, {x, y, z}), d = p - at;
                        const float r = glm::length(d);
                        if (glm::any(glm::lessThan(p, glm::vec3(0.0f))) || glm::any(glm::greaterThan(p, glm::vec3(kCube - 1.0f))))
                            continue;
                        const float got = directAt(v, {x, y, z})[0];
                        ASSERT_TRUE(std::isfinite(got) && got > 0.0f) << x << " " << y << " " << z;
                        if (r < 0.5f) continue;
                        const float exact = intensity * std::exp(-sigma * r) / (r * r);
                        const glm::vec3 a = glm::abs(d);
                        const float top = glm::max(a.x, glm::max(a.y, a.z));
                        const bool on_ray = centred && (a.x == 0 || a.x == top) && (a.y == 0 || a.y == top) && (a.z == 0 || a.z == top);
                        const float depth_error = std::abs(std::log(got / exact));
                        if (on_ray || sigma < 1e-3f) exact_cells = std::max(exact_cells, std::abs(got - exact) / exact);
                        else excess = std::max(excess, depth_error / sigma - 0.07f * r);
                    }
            std::printf("  sigma %g, light at (%g, %g, %g): exact cells %.2g relative; optical depth within 0.07 sigma r "
                        "+ %.2g sigma\n", sigma, at.x, at.y, at.z, exact_cells, excess);
            EXPECT_LT(exact_cells, 2e-5f);
            EXPECT_LT(excess, 0.7f);
        }
    }
}

// A point sweep computes cells only up to slope 3 + blur radius per slice (counted from one slice
// behind the light) and leaves the rest dark. The cells it weights must not notice: all six
// sweeps of a light between cell centres inside a 64^3 medium, and of one beside it, direct and
// blurred indirect, give volumes bit-identical to sweeps that compute up to slope 40.
TEST(MultiLight, PointSweepsComputeFarEnoughSideways) {
    const glm::ivec3 dims(64);
    const std::vector<float> sigma(size_t(dims.x) * dims.y * dims.z, 0.03f);
    const kernel::VxParams march{};
    const Indirect blur;
    const float tan_half = std::tan(glm::radians(0.5f * blur.angle));
    for (glm::vec3 at : {glm::vec3(31.7f, 32.2f, 32.45f), glm::vec3(-3.0f, 32.0f, 32.0f)})
        for (bool indirect : {false, true}) {
            auto sweep = [&](int reach) {
                IlluminationVolume v;
                v.dims = dims;
                v.values.assign(3 * v.cells(), 0.0f);
                kernel::VxPropParams Q{};
                Q.grid_to_world = Q.world_to_grid = glm::mat4(1.0f);
                Q.dims = dims;
                Q.channels = indirect ? 3 : 1;
                const auto taps = indirect ? blurTaps(blur) : directTaps();
                for (size_t k = 0; k < taps.size(); ++k) Q.taps[k] = taps[k];
                Q.tap_count = int(taps.size());
                Q.source = at;
                Q.source_is_position = 1;
                Q.flow = 1.0f;
                Q.blur_tan = indirect ? tan_half : 0.0f;
                Q.weight = 1.0f;
                Q.per_cell_flow = 1;
                Q.max_slope = reach;
                Q.atten = indirect ? -glm::log(blur.transport_color) : glm::vec3(1.0f);
                Q.cells_per_voxel = 1.0f;
                Q.tint = glm::vec3(1.0f);
                Q.light.position = at;
                Q.light.type = VX_LIGHT_POINT;
                Q.light.color = glm::vec3(100.0f);
                PropagationPass pass;
                pass.march = &march;
                pass.sigma = &sigma;
                CpuSweepScratch scratch;
                for (int axis = 0; axis < 3; ++axis)
                    for (int sign : {-1, 1}) {
                        Q.axis = axis;
                        Q.direction = sign;
                        pass.sweeps = {Q};
                        propagateCpu(pass, v, scratch);
                    }
                return v.values;
            };
            const int reach = 3 + int(std::ceil(std::sqrt(3.0f) * (indirect ? tan_half : 0.0f)));   // as the stage sets it
            const std::vector<float> near = sweep(reach), far = sweep(40);
            size_t differ = 0;
            for (size_t i = 0; i < far.size(); ++i) differ += near[i] != far[i];
            EXPECT_EQ(differ, 0u) << "light at " << at.x << " " << at.y << " " << at.z << (indirect ? ", indirect" : "");
        }
}

TEST(MultiLight, PointLightInsideTheMediumIsAnalyticOnCpu) {
    auto cpu = makeCpuBackend();
    expectPointLightInsideCube(*cpu);
}

TEST(MultiLight, PointLightInsideTheMediumIsAnalyticOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    expectPointLightInsideCube(*gl);
}

// A mixed rig: a directional key, a point light inside the cube, a spot from outside, a point
// light beside the volume, with indirect light.
std::vector<Light> mixedRig() {
    Light spot = coloredPointLight({12, 30, 12}, {0.3f, 0.5f, 1.0f}, 400.0f);
    spot.type = LightType::Spot;
    spot.direction = glm::vec3(0, -1, 0);
    spot.cone_angle = 35.0f;
    spot.cone_softness = 10.0f;
    return {coloredDirectionalLight({0.3f, -1, 0.2f}, {1.0f, 0.9f, 0.8f}, 3.0f), coloredPointLight({9.5f, 13.2f, 11.1f}, {1, 0.4f, 0.1f}, 20.0f),
            spot, coloredPointLight({-3.0f, 5.0f, 20.0f}, {0.2f, 1.0f, 0.3f}, 150.0f)};
}

float relativeL2(const std::vector<float>& got, const std::vector<float>& want) {
    double diff = 0.0, norm = 0.0;
    for (size_t i = 0; i < want.size(); ++i) {
        diff += double(got[i] - want[i]) * double(got[i] - want[i]);
        norm += double(want[i]) * double(want[i]);
    }
    return float(std::sqrt(diff / norm));
}

// Light adds: the volume of lights A and B is the sum of their volumes (both blocks), and the
// coherent passes give what one pass per light gives.
TEST(MultiLight, LightsAddUpAndCoherentPassesMatchSequentialOnes) {
    auto cpu = makeCpuBackend();
    auto grid = boxGrid({0, 0, 0}, {kCube - 1, kCube - 1, kCube - 1}, 0.08f);
    const std::vector<Light> rig = mixedRig();
    auto all = illuminate(grid, cubeScene(rig, true), *cpu, Camera{});
    std::vector<float> sum(all->volume().values.size(), 0.0f);
    for (const Light& l : rig) {
        auto one = illuminate(grid, cubeScene({l}, true), *cpu, Camera{});
        ASSERT_EQ(one->volume().values.size(), sum.size());
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += one->volume().values[i];
    }
    const float additivity = relativeL2(all->volume().values, sum);
    Scene sequential = cubeScene(rig, true);
    sequential.effects.propagation.coherent = false;
    auto seq = illuminate(grid, sequential, *cpu, Camera{});
    const float coherence = relativeL2(all->volume().values, seq->volume().values);
    std::printf("  A+B against A plus B: %.2g; coherent against sequential: %.2g (relative L2)\n", additivity, coherence);
    EXPECT_LT(additivity, 1e-6f);
    EXPECT_LT(coherence, 1e-6f);
    EXPECT_EQ(seq->update().passes, seq->update().sweeps);
    EXPECT_LE(all->update().passes, 12);   // at most six directions per block
}

// Both backends give the same volume for the mixed rig (point light inside, spot, a light beside
// the volume, indirect light), with blending on.
TEST(MultiLight, CpuAndGlAgreeOnAMixedRig) {
    VOXLUX_REQUIRE_GL(gl);
    auto cpu = makeCpuBackend();
    auto grid = boxGrid({0, 0, 0}, {kCube - 1, kCube - 1, kCube - 1}, 0.08f);
    Scene scene = cubeScene(mixedRig(), true);
    scene.effects.propagation.blend_axes = true;
    auto a = illuminate(grid, scene, *cpu, Camera{});
    auto b = illuminate(grid, scene, *gl, Camera{});
    const auto& va = a->volume().values;
    const auto& vb = b->volume().values;
    ASSERT_EQ(va.size(), vb.size());
    float peak = 0.0f, worst = 0.0f;
    for (size_t i = 0; i < va.size(); ++i) {
        peak = std::max(peak, std::abs(va[i]));
        worst = std::max(worst, std::abs(va[i] - vb[i]));
    }
    std::printf("  mixed rig, cpu against gl: max %.2g of peak\n", worst / peak);
    EXPECT_LT(worst, 1e-4f * peak);
}

// The noisy ball (test_support's writeBall, written to a folder of its own), shadowed by
// propagation with indirect light, on `backend`, at `light_resolution` cells.
Scene ballScene(const std::string& folder, int light_resolution, Backend backend = Backend::Cpu) {
    Scene scene;
    scene.volume().path = writeBall(tempDir(folder));
    scene.volume().material.density_scale = 8.0f;
    scene.render.backend = backend;
    scene.effects.shadows = ShadowMethod::Propagation;
    scene.effects.light_resolution = light_resolution;
    scene.effects.indirect = Indirect{};
    return scene;
}

// A random edit of one light: move, recolour, re-intensify, toggle or change its type.
void randomEdit(LightRig& rig, std::mt19937& rng, float extent) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const auto ids = rig.ids();
    const float pick = u(rng);
    auto randomPosition = [&] { return glm::vec3(u(rng), u(rng), u(rng)) * (1.6f * extent) - 0.3f * extent; };
    auto randomLight = [&] {
        Light l;
        const float t = u(rng);
        l.type = t < 0.4f ? LightType::Directional : t < 0.75f ? LightType::Point : LightType::Spot;
        l.direction = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) - 0.5f + glm::vec3(0, 1e-3f, 0));
        l.position = randomPosition();
        l.color = glm::vec3(u(rng), u(rng), u(rng));
        l.intensity = l.type == LightType::Directional ? 3.0f * u(rng) : 300.0f * u(rng);
        return l;
    };
    if (pick < 0.05f && ids.size() < 8) {
        rig.add(randomLight());
        return;
    }
    const int id = ids[size_t(u(rng) * float(ids.size())) % ids.size()];
    if (pick < 0.1f && ids.size() > 2) {
        rig.remove(id);
        return;
    }
    Light l = rig.light(id);
    if (pick < 0.35f) {
        l.position += (glm::vec3(u(rng), u(rng), u(rng)) - 0.5f) * 4.0f;
        l.direction = glm::normalize(l.direction + (glm::vec3(u(rng), u(rng), u(rng)) - 0.5f) * 0.3f);
    } else if (pick < 0.55f) {
        l.color = glm::vec3(u(rng), u(rng), u(rng));
    } else if (pick < 0.7f) {
        l.intensity *= 0.5f + u(rng);
    } else if (pick < 0.85f) {
        rig.toggle(id, !l.enabled);
        return;
    } else {
        const Light fresh = randomLight();
        l.type = fresh.type;
        l.intensity = fresh.intensity;
    }
    rig.update(id, l);
}

// The issue's equivalence test: after 1000 random edits applied selectively (the stage picks
// selective or entire by its estimate, and re-bases when float residue could build up), the
// volume equals one computed from scratch for the final lights. Norm: L2 over every value of
// both blocks, relative to the from-scratch volume's L2.
void expectEditsMatchFromScratch(Backend backend, int light_resolution) {
    Scene scene = ballScene("multilight_edits", light_resolution, backend);
    scene.lights = {coloredDirectionalLight({0.3f, -1, 0.2f}, {1, 0.9f, 0.8f}, 3.0f), coloredPointLight({0.2f, -0.3f, 0.1f}, {1, 0.5f, 0.2f}, 2.0f),
                    coloredPointLight({3, 1, -2}, {0.3f, 0.6f, 1.0f}, 20.0f), coloredDirectionalLight({-1, 0.2f, 0.5f}, {0.5f, 0.5f, 1}, 1.0f)};
    Renderer renderer(scene);
    LightRig rig(renderer, scene);
    rig.apply();
    std::mt19937 rng(2015);
    int selective = 0, entire = 0, rebases = 0;
    for (int n = 0; n < 1000; ++n) {
        randomEdit(rig, rng, 2.0f);
        const LightRigUpdate u = rig.apply();
        if (!u.lighting) continue;   // every light off: the stage is not needed and keeps its volume
        selective += u.lighting->mode == LightUpdate::Mode::Selective;
        entire += u.lighting->mode == LightUpdate::Mode::Entire;
        rebases += u.lighting->reason.rfind("re-base", 0) == 0;
    }
    Renderer fresh(rig.scene());
    fresh.prepare(std::nullopt, false);
    const auto& got = renderer.lightingOutput<IlluminationVolume>()->values;
    const auto& want = fresh.lightingOutput<IlluminationVolume>()->values;
    ASSERT_EQ(got.size(), want.size());
    float peak = 0.0f, worst = 0.0f;
    for (size_t i = 0; i < want.size(); ++i) {
        peak = std::max(peak, std::abs(want[i]));
        worst = std::max(worst, std::abs(got[i] - want[i]));
    }
    const float l2 = relativeL2(got, want);
    std::printf("  1000 edits: %d selective, %d entire (%d re-bases); relative L2 %.2g, max %.2g of peak\n", selective,
                entire, rebases, l2, worst / peak);
    EXPECT_LT(l2, 1e-4f);
    EXPECT_GT(selective, 2 * entire);
}

TEST(MultiLight, ThousandRandomEditsMatchFromScratchOnCpu) { expectEditsMatchFromScratch(Backend::Cpu, 24); }

TEST(MultiLight, ThousandRandomEditsMatchFromScratchOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    expectEditsMatchFromScratch(Backend::Gl, 12);
}

// Off then on takes the light out and puts it back selectively, restoring the volume.
TEST(MultiLight, ToggleOffAndOnRestoresTheVolume) {
    Scene scene = ballScene("multilight_toggle", 32);
    for (int k = 0; k < 6; ++k)
        scene.lights.push_back(coloredDirectionalLight({std::cos(float(k)), -1.0f, std::sin(float(k))}, {1, 0.2f * float(k), 0.5f}, 2.0f));
    Renderer renderer(scene);
    LightRig rig(renderer, scene);
    rig.apply();
    const std::vector<float> before = renderer.lightingOutput<IlluminationVolume>()->values;
    rig.toggle(2, false);
    const LightRigUpdate off = rig.apply();
    ASSERT_TRUE(off.lighting);
    EXPECT_EQ(off.lighting->mode, LightUpdate::Mode::Selective);
    EXPECT_EQ(off.lighting->lights_out, 1);
    EXPECT_EQ(off.lighting->lights_in, 0);
    EXPECT_EQ(off.dirty, std::vector<int>{2});
    EXPECT_GT(relativeL2(renderer.lightingOutput<IlluminationVolume>()->values, before), 0.01f);
    rig.toggle(2, true);
    const LightRigUpdate on = rig.apply();
    EXPECT_EQ(on.lighting->mode, LightUpdate::Mode::Selective);
    const float restored = relativeL2(renderer.lightingOutput<IlluminationVolume>()->values, before);
    std::printf("  toggled off and on: relative L2 %.2g; one toggle walked %lld slices in %d passes\n", restored,
                on.lighting->slices, on.lighting->passes);
    EXPECT_LT(restored, 1e-5f);
}

// With the eye pass on, a selective update goes to the light sweeps' indirect block kept for the
// eye pass, and the eye pass re-runs from it: the same as a fresh volume.
TEST(MultiLight, SelectiveUpdatesUnderTheEyePassMatchFromScratch) {
    Scene scene = ballScene("multilight_eye", 24);
    scene.effects.propagation.eye_pass = true;
    scene.lights = {coloredDirectionalLight({0.3f, -1, 0.2f}, {1, 0.9f, 0.8f}, 3.0f), coloredDirectionalLight({-1, -0.2f, 0.4f}, {0.4f, 0.5f, 1}, 2.0f),
                    coloredDirectionalLight({0.1f, 0.3f, -1}, {1, 0.3f, 0.3f}, 1.0f)};
    Renderer renderer(scene);
    LightRig rig(renderer, scene);
    rig.apply();
    Light moved = rig.light(1);
    moved.direction = glm::normalize(glm::vec3(-1, -0.4f, 0.3f));
    rig.update(1, moved);
    const LightRigUpdate u = rig.apply();
    ASSERT_EQ(u.lighting->mode, LightUpdate::Mode::Selective) << u.lighting->reason;
    Renderer fresh(rig.scene());
    fresh.prepare(std::nullopt, false);
    const float error = relativeL2(renderer.lightingOutput<IlluminationVolume>()->values, fresh.lightingOutput<IlluminationVolume>()->values);
    std::printf("  selective update under the eye pass: relative L2 %.2g against a fresh volume\n", error);
    EXPECT_LT(error, 1e-5f);
}

// HDR: a 1e6 light beside a 1e-3 light. Both stay finite and keep their ratio; taking the strong
// one out re-bases instead of leaving its float residue on the weak one.
TEST(MultiLight, HdrExtremesStayFiniteAndKeepTheirRatio) {
    auto cpu = makeCpuBackend();
    auto grid = boxGrid({0, 0, 0}, {kCube - 1, kCube - 1, kCube - 1}, 0.05f);
    const Light strong = coloredDirectionalLight({0, -1, 0}, {1, 0, 0}, 1e6f), weak = coloredDirectionalLight({0, -1, 0.3f}, {0, 0, 1}, 1e-3f);
    auto both = illuminate(grid, cubeScene({strong, weak}, true), *cpu, Camera{});
    auto alone = illuminate(grid, cubeScene({weak}, true), *cpu, Camera{});
    const IlluminationVolume& v = both->volume();
    float red = 0.0f, blue = 0.0f;
    for (size_t i = 0; i < v.values.size(); ++i) ASSERT_TRUE(std::isfinite(v.values[i])) << i;
    for (size_t c = 0; c < v.cells(); ++c) red = std::max(red, v.values[3 * c]), blue = std::max(blue, v.values[3 * c + 2]);
    EXPECT_NEAR(red / blue, 1e9f, 1e9f * 1e-4f);
    // Out with the strong light: the stage re-bases, so the weak light's volume is exact.
    Scene weak_only = cubeScene({weak}, true);
    both->relight(weak_only);
    EXPECT_EQ(both->update().mode, LightUpdate::Mode::Entire);
    EXPECT_EQ(both->update().reason.rfind("re-base", 0), 0u) << both->update().reason;
    EXPECT_LT(relativeL2(both->volume().values, alone->volume().values), 1e-6f);
}

TEST(LightRig, TracksIdsAndDirtyLightsAndRefusesUnknownOnes) {
    Scene scene = ballScene("multilight_rig", 16);
    Light key = coloredDirectionalLight({0, -1, 0}, glm::vec3(1), 2.0f);
    key.name = "key";
    scene.lights = {key, coloredPointLight({3, 0, 0}, glm::vec3(1), 10.0f)};
    Renderer renderer(scene);
    LightRig rig(renderer, scene);
    EXPECT_EQ(rig.ids(), (std::vector<int>{0, 1}));
    EXPECT_EQ(rig.find("key"), 0);
    EXPECT_FALSE(rig.find("rim"));
    EXPECT_EQ(rig.light(1).type, LightType::Point);
    const LightRigUpdate first = rig.apply();
    EXPECT_EQ(first.lighting->mode, LightUpdate::Mode::Entire);
    EXPECT_EQ(first.lighting->reason, "first update");
    const int added = rig.add(coloredDirectionalLight({1, -1, 0}, glm::vec3(0.5f), 1.0f));
    EXPECT_EQ(added, 2);
    rig.remove(0);
    EXPECT_EQ(rig.dirty(), (std::vector<int>{0, 2}));
    const LightRigUpdate u = rig.apply();
    EXPECT_EQ(u.lighting->mode, LightUpdate::Mode::Selective) << u.lighting->reason;
    EXPECT_TRUE(rig.dirty().empty());
    EXPECT_EQ(u.lighting->lights, 2);
    EXPECT_EQ(u.lighting->lights_out, 1);
    EXPECT_EQ(u.lighting->lights_in, 1);
    EXPECT_GT(u.lighting->slices, 0);
    const LightRigUpdate none = rig.apply();
    EXPECT_EQ(none.lighting->mode, LightUpdate::Mode::Kept);
    EXPECT_EQ(none.lighting->slices, 0);
    try {
        rig.update(7, key);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "light rig: no light with id 7");
    }
}

// `render --light-edit`: each edit is timed on its own line and the final frame is written; a
// bad edit file is refused before anything is written.
TEST(Cli, LightEditsReplayAndReportEachEdit) {
    const std::string dir = tempDir("cli_light_edit");
    const std::string ball = writeBall(dir);
    const std::string scene_path = dir + "/rig.json", edits_path = dir + "/edits.json", out = dir + "/rig.exr";
    std::ofstream(scene_path) << R"({"volume": {"path": "ball.vdb"}, "render": {"resolution": [48, 32], "backend": "cpu"},
      "effects": {"shadows": "propagation", "light_resolution": 24},
      "lights": [{"name": "key", "type": "directional", "direction": [0, -1, 0], "intensity": 3},
                 {"name": "fill", "type": "directional", "direction": [1, 0, -1], "intensity": 1},
                 {"name": "glow", "type": "point", "position": [0, 0, 0], "color": [1, 0.5, 0.2], "intensity": 2}]})";
    std::ofstream(edits_path) << R"({"edits": [{"light": "key", "set": {"color": [1, 0.8, 0.6]}},
      {"toggle": "glow"}, {"add": {"name": "rim", "type": "point", "position": [0, 0, -4], "intensity": 40}},
      {"light": 1, "set": {"type": "spot", "position": [-4, 0, 4], "cone_angle": 30, "cone_softness": 5}}, {"remove": "rim"}]})";
    CliResult r = runCli("render " + scene_path + " --light-edit " + edits_path + " -o " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* line : {"initial", "1: update key", "2: toggle glow off", "3: add rim", "4: update fill", "5: remove rim"})
        EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
    EXPECT_NE(r.out.find("selective"), std::string::npos) << r.out;
    EXPECT_TRUE(std::filesystem::exists(out));

    std::ofstream(edits_path) << R"({"edits": [{"light": "key", "set": {"intensity": 2}}, {"remove": "rim"}]})";
    const std::string missing = dir + "/never.exr";
    r = runCli("render " + scene_path + " --light-edit " + edits_path + " -o " + missing);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + edits_path + ": /edits/1/remove: no light named \"rim\" (named lights: key, fill, glow)\n");
    EXPECT_FALSE(std::filesystem::exists(missing));
}

}  // namespace
}  // namespace voxlux::test
