// Per-material transport colour (Kniss 2003 Eq. 8 with a 2D transfer function's regions): the
// indirect sweep's optical depth per channel follows each cell's own -ln(transport), exactly as
// the trapezoid rule integrates it, on both backends and through the whole pipeline.
#include <cmath>

#include "backend/backend_choice.h"
#include "kernel/cpu_kernel_data.h"
#include "lighting/propagation/light_sweeps.h"
#include "lighting/propagation/propagation_passes.h"
#include "render/renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// Two materials stacked along the sweep's axis: extinction and -ln(transport) per channel.
struct Layer {
    float sigma;
    glm::vec3 k;
};
constexpr Layer kNear{0.3f, {0.1f, 0.5f, 1.2f}}, kFar{0.5f, {0.8f, 0.2f, 0.05f}};

// A directional light's indirect sweep along `axis` (direction `sign`), unblurred, through
// kNear in the first half of the slices it meets and kFar in the second: the illumination volume.
IlluminationVolume sweepTwoLayers(Device device, int axis, int sign) {
    const glm::ivec3 dims(axis == 0 ? 14 : 5, axis == 1 ? 14 : 6, axis == 2 ? 14 : 7);
    const size_t cells = size_t(dims.x) * dims.y * dims.z;
    std::vector<float> planes(4 * cells);   // extinction, then it times k per channel
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const int s = glm::ivec3(x, y, z)[axis];
                const bool near = (sign > 0 ? s : dims[axis] - 1 - s) < dims[axis] / 2;
                const Layer& l = near ? kNear : kFar;
                const size_t i = (size_t(z) * dims.y + y) * dims.x + x;
                planes[i] = l.sigma;
                for (int c = 0; c < 3; ++c) planes[(c + 1) * cells + i] = l.sigma * l.k[c];
            }
    const std::vector<kernel::VxTap> taps = directTaps();
    kernel::VxPropParams Q{};
    Q.grid_to_world = glm::mat4(1.0f);
    Q.world_to_grid = glm::mat4(1.0f);
    Q.dims = dims;
    Q.channels = 3;
    Q.axis = axis;
    Q.direction = sign;
    Q.tap_count = int(taps.size());
    for (size_t t = 0; t < taps.size(); ++t) Q.taps[t] = taps[t];
    Q.light.type = VX_LIGHT_DIRECTIONAL;
    Q.light.direction[axis] = float(sign);
    Q.light.color = glm::vec3(1.0f);
    Q.source = Q.light.direction;
    Q.flow = 1.0f;
    Q.weight = 1.0f;
    Q.atten = glm::vec3(7.0f);   // unused with transport planes: it would black everything out
    Q.transport_planes = 1;
    Q.cells_per_voxel = 1.0f;
    Q.tint = glm::vec3(1.0f);
    const kernel::VxParams march{};
    const std::vector<glm::vec4> noise(1);
    PropagationPass pass;
    pass.sweeps = {Q};
    pass.march = &march;
    pass.sigma = &planes;
    pass.noise = &noise;
    IlluminationVolume volume;
    volume.dims = dims;
    volume.values.assign(3 * cells, 0.0f);
    makePropagationPasses(device)->propagate(pass, volume);
    return volume;
}

// What the sweep's composite trapezoid gives at the m-th slice the light meets: each step from
// slice m - 1 (outside the grid: nothing) to m adds half of each end's extinction times k.
glm::vec3 expectedTwoLayers(int m, int slices) {
    glm::vec3 depth(0.0f), before(0.0f);
    for (int n = 0; n <= m; ++n) {
        const Layer& l = n < slices / 2 ? kNear : kFar;
        const glm::vec3 here = l.sigma * l.k;
        depth += 0.5f * (before + here);
        before = here;
    }
    return glm::exp(-depth);
}

void expectTwoLayers(Device device, const char* name) {
    for (int axis : {0, 2})
        for (int sign : {-1, 1}) {
            const IlluminationVolume v = sweepTwoLayers(device, axis, sign);
            for (int z = 0; z < v.dims.z; ++z)
                for (int y = 0; y < v.dims.y; ++y)
                    for (int x = 0; x < v.dims.x; ++x) {
                        const int s = glm::ivec3(x, y, z)[axis];
                        const glm::vec3 want = expectedTwoLayers(sign > 0 ? s : v.dims[axis] - 1 - s, v.dims[axis]);
                        const float* got = &v.values[((size_t(z) * v.dims.y + y) * v.dims.x + x) * 3];
                        for (int c = 0; c < 3; ++c)
                            ASSERT_NEAR(got[c], want[c], 2e-6f * want[c] + 1e-7f)
                                << name << ", axis " << axis << ", sign " << sign << ", cell " << x << " " << y << " " << z << ", channel " << c;
                    }
        }
}

// Across the interface the step's depth is the trapezoid of each channel's own extinction times
// k: neither material's colour alone, nor the mean colour times the step's extinction. The x
// sweep runs on the slice-major copy of all four planes, the z sweep on the row batch.
TEST(MaterialTransport, TwoLayersFollowTheTrapezoidOfEachChannelOnCpu) { expectTwoLayers(Device::Cpu, "cpu"); }

TEST(MaterialTransport, TwoLayersFollowTheTrapezoidOfEachChannelOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    expectTwoLayers(Device::Gl, "gl");
}

TransferRegion valueBand(float lo, float hi, float extinction, std::optional<glm::vec3> transport) {
    TransferRegion r;
    r.value = {lo, hi};
    r.extinction = extinction;
    r.transport = transport;
    return r;
}

// The two halves, Kniss indirect light from above (unblurred, so that each column keeps its own
// material), regions carrying `left` and `right` (or none), the global colour `global`.
Scene halvesScene(std::optional<glm::vec3> left, std::optional<glm::vec3> right, glm::vec3 global, bool chroma) {
    Scene s;
    s.volume().path = "halves";
    s.render.width = 32;
    s.render.height = 32;
    s.volume().material.transfer_2d = {valueBand(40, 60, 0.1f, left), valueBand(90, 110, 0.2f, right)};
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.light_resolution = 40;
    s.effects.propagation.chroma_subsampling = chroma;
    Indirect in;
    in.model = IndirectModel::Kniss;
    in.transport_color = global;
    in.angle = 0.0f;
    s.effects.indirect = in;
    Light l;
    l.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    s.lights = {l};
    return s;
}

std::unique_ptr<Lit> illuminateHalves(const Scene& scene, KernelBackend& backend) {
    Camera camera;
    camera.position = glm::vec3(16, 60, 90);
    camera.look_at = glm::vec3(16, 16, 16);
    return illuminate(twoHalvesGrid(50.0f, 100.0f), scene, backend, camera);
}

// The same transport colour on every region is the global colour: the light grid's box filter,
// the planes (chroma subsampled or not) and the sweeps reproduce the one-colour path.
void expectOneColourIsTheGlobalColour(KernelBackend& backend, const char* name) {
    const glm::vec3 colour(0.9f, 0.6f, 0.4f);
    for (bool chroma : {false, true}) {
        auto global = illuminateHalves(halvesScene(std::nullopt, std::nullopt, colour, chroma), backend);
        auto regions = illuminateHalves(halvesScene(colour, colour, glm::vec3(0.3f, 0.5f, 0.7f), chroma), backend);
        const auto& a = global->volume().values;
        const auto& b = regions->volume().values;
        ASSERT_EQ(a.size(), b.size());
        float peak = 0.0f, worst = 0.0f;
        for (size_t i = 0; i < a.size(); ++i) {
            peak = std::max(peak, std::abs(a[i]));
            worst = std::max(worst, std::abs(a[i] - b[i]));
        }
        EXPECT_GT(peak, 0.1f) << name;
        EXPECT_LT(worst, 2e-6f * peak) << name << (chroma ? ", chroma subsampled" : "");
    }
}

TEST(MaterialTransport, OneColourOnEveryRegionIsTheGlobalColourOnCpu) {
    auto cpu = makeCpuBackend();
    expectOneColourIsTheGlobalColour(*cpu, "cpu");
}

TEST(MaterialTransport, OneColourOnEveryRegionIsTheGlobalColourOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    expectOneColourIsTheGlobalColour(*gl, "gl");
}

// Each half tints its indirect light by its own colour (Kniss Fig. 9, per material): deep in
// the left half red outlasts blue, deep in the right half blue outlasts red, at the rate
// ln(red / blue) = (k_blue - k_red) * extinction * depth of that half's colour.
TEST(MaterialTransport, EachRegionTintsTheIndirectLightByItsOwnColour) {
    auto cpu = makeCpuBackend();
    const glm::vec3 warm(1.0f, 0.6f, 0.3f), cool(0.3f, 0.6f, 1.0f);
    auto lit = illuminateHalves(halvesScene(warm, cool, glm::vec3(0.6f), false), *cpu);
    const IlluminationVolume& v = lit->volume();
    ASSERT_EQ(v.chroma_dims, v.dims);
    int checked = 0;
    for (const auto& [x_voxel, colour, sigma] : {std::tuple{4, warm, 0.1f}, std::tuple{27, cool, 0.2f}}) {
        for (int y = 0; y < v.dims.y; ++y) {
            const glm::vec3 centre = glm::vec3(glm::inverse(v.world_to_illum) * glm::vec4(glm::vec3(0, y, 0) + 0.5f, 1.0f));
            const glm::ivec3 cell = glm::ivec3(glm::vec3(v.world_to_illum * glm::vec4(float(x_voxel), centre.y, 16.0f, 1.0f)));
            if (centre.y < 0.5f || centre.y > 30.5f) continue;   // inside the cube, clear of its faces' half-empty cells
            const float* c = &v.values[v.indirectOffset() + ((size_t(cell.z) * v.dims.y + cell.y) * v.dims.x + cell.x) * 3];
            const float depth = 31.5f - centre.y;
            const float want = (std::log(colour.x) - std::log(colour.z)) * sigma * depth;
            EXPECT_NEAR(std::log(c[0] / c[2]), want, 1e-3f * (1.0f + depth)) << "x " << x_voxel << ", y " << y;
            ++checked;
        }
    }
    EXPECT_GE(checked, 50);
}

}  // namespace
}  // namespace voxlux::test
