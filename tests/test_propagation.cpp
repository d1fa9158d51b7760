// Illumination-volume propagation (Ropinski 2010, Kniss 2003): sweep geometry and blur weights,
// analytic slabs on both backends, energy, transport colour, popping, perturbation, and the two
// backends against each other.
#include <cmath>

#include "cpu_kernel.h"
#include "illumination_stage.h"
#include "light_sweeps.h"
#include "renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr int kSlab = 32;   // voxels per side of the slab tests' cube
// Cells of the light grid along its side at one cell per voxel: the occupied bricks reach one
// brick below the cube (the bricks holding the voxels' trilinear neighbours).
constexpr int kSlabGrid = kSlab + 8;

// A homogeneous cube of extinction `sigma` (voxel size 1) lit by one white directional light
// travelling along `dir`, with propagation shadows on a light grid of one cell per voxel.
Scene slabScene(glm::vec3 dir, bool blend) {
    Scene s;
    s.volume.path = "slab";
    s.render.width = 32;
    s.render.height = 32;
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.light_resolution = kSlabGrid;
    s.effects.propagation.blend_axes = blend;
    Light l;
    l.direction = glm::normalize(dir);
    s.lights = {l};
    return s;
}

struct Lit {
    std::unique_ptr<Prepared> prepared;
    IlluminationStage stage;
    StageTimes times;
    std::vector<std::string> reused, warnings;
};

// Runs the illumination stage for `scene` over `grid` on `backend`.
std::unique_ptr<Lit> illuminate(openvdb::FloatGrid::Ptr grid, const Scene& scene, KernelBackend& backend) {
    auto lit = std::make_unique<Lit>();
    Camera camera;
    camera.position = glm::vec3(16, 60, 90);
    camera.look_at = glm::vec3(16, 16, 16);
    lit->prepared = prepare(volumeFromGrid(grid), scene, camera);
    lit->stage.update(scene, camera, "test", lit->prepared->inputs, backend, lit->times, lit->reused, lit->warnings);
    return lit;
}

// Length of the ray from cell centre c (index space; the cube spans [-0.5, kSlab - 0.5]) back
// towards a light travelling along `dir`, inside the cube.
float depthInCube(glm::vec3 c, glm::vec3 dir) {
    float t = 1e30f;
    for (int a = 0; a < 3; ++a) {
        if (dir[a] == 0.0f) continue;
        const float face = dir[a] < 0.0f ? float(kSlab) - 0.5f : -0.5f;  // the face the light came through
        t = std::min(t, (face - c[a]) / -dir[a]);
    }
    return t;
}

float luminanceAt(const IlluminationVolume& v, glm::ivec3 c) {
    return v.values[(size_t(c.z) * v.dims.y + c.y) * v.dims.x + c.x];
}

// Index-space centre of cell c (voxel size 1: index space is world space).
glm::vec3 cellCentre(const IlluminationVolume& v, glm::ivec3 c) {
    return glm::vec3(glm::inverse(v.world_to_illum) * glm::vec4(glm::vec3(c) + 0.5f, 1.0f));
}

bool insideCube(glm::vec3 p, float margin) {
    return glm::all(glm::greaterThanEqual(p, glm::vec3(margin - 0.5f))) &&
           glm::all(glm::lessThanEqual(p, glm::vec3(float(kSlab) - 0.5f - margin)));
}

// Errors of the direct luminance against exp(-sigma d):
//  - `cone`: relative, over the cells whose whole domain of dependence (a bilinear read reaches
//    one cell sideways per slice) lies where the light entered through the top face, the
//    uniform slices where the reads are exact;
//  - `envelope`: absolute, over all cells inside the cube, beyond the range of the exact values
//    of the cell and its 8 sideways neighbours in its slice (a bilinear read is a convex mix of
//    them: near an edge where two faces let light in the reads blur across it, never beyond).
struct SlabError {
    float cone = 0.0f;
    float envelope = 0.0f;
};
SlabError slabError(const IlluminationVolume& v, float sigma, glm::vec3 dir) {
    SlabError e;
    dir = glm::normalize(dir);
    auto exact = [&](glm::vec3 c) { return std::exp(-sigma * depthInCube(c, dir)); };
    for (int z = 0; z < v.dims.z; ++z)
        for (int y = 0; y < v.dims.y; ++y)
            for (int x = 0; x < v.dims.x; ++x) {
                const glm::vec3 c = cellCentre(v, {x, y, z});
                if (!insideCube(c, 0.0f)) continue;
                const float got = luminanceAt(v, {x, y, z});
                float lo = 1.0f, hi = 0.0f;
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const glm::vec3 n = c + glm::vec3(dx, 0, dz);
                        const float t = insideCube(n, 0.0f) ? exact(n) : 1.0f;
                        lo = std::min(lo, t);
                        hi = std::max(hi, t);
                    }
                e.envelope = std::max(e.envelope, std::max(lo - got, got - hi));
                const float d = depthInCube(c, dir);
                const glm::vec3 entry = c - dir * d;
                const float slices = float(kSlab) - 0.5f - c.y;
                const bool in_cone = std::abs(entry.y - (kSlab - 0.5f)) < 1e-3f &&
                                     insideCube(glm::vec3(c.x, 16.0f, c.z), slices + 1.0f) &&
                                     insideCube(glm::vec3(entry.x, 16.0f, entry.z), slices + 1.0f);
                if (in_cone) e.cone = std::max(e.cone, std::abs(got - exact(c)) / exact(c));
            }
    return e;
}

openvdb::FloatGrid::Ptr slab(float sigma) { return boxGrid({0, 0, 0}, {kSlab - 1, kSlab - 1, kSlab - 1}, sigma); }

TEST(Sweeps, PrincipalAxisAndRopinskiBlendWeights) {
    // Along an axis: one sweep, whichever way the light travels.
    auto s = sweepsFor({0, -2, 0}, true);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s[0].axis, 1);
    EXPECT_EQ(s[0].sign, -1);
    EXPECT_FLOAT_EQ(s[0].weight, 1.0f);
    // In the xz plane at 30 degrees from z: alpha_0 = 1 - 2 * 30 deg / pi = 2/3 on z, 1/3 on x.
    const float a = glm::radians(30.0f);
    s = sweepsFor({std::sin(a), 0, std::cos(a)}, true);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0].axis, 2);
    EXPECT_EQ(s[1].axis, 0);
    EXPECT_NEAR(s[0].weight, 2.0f / 3.0f, 1e-6f);
    EXPECT_NEAR(s[1].weight, 1.0f / 3.0f, 1e-6f);
    // Without blending the principal axis takes everything.
    s = sweepsFor({std::sin(a), 0, std::cos(a)}, false);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s[0].axis, 2);
    // The body diagonal splits evenly; weights always sum to 1.
    s = sweepsFor({-1, -1, -1}, true);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_FLOAT_EQ(s[0].weight + s[1].weight, 1.0f);
    EXPECT_FLOAT_EQ(s[0].weight, 0.5f);
    EXPECT_EQ(s[0].sign, -1);
}

// Each axis's weight as a function of direction: continuous across every swap of axes.
TEST(Sweeps, WeightsAreContinuousWhereAxesSwap) {
    auto weightOn = [](glm::vec3 f, int axis) {
        float w = 0.0f;
        for (const Sweep& s : sweepsFor(f, true)) w += s.axis == axis ? s.weight : 0.0f;
        return w;
    };
    for (float tilt : {0.0f, 0.2f, 0.5f}) {        // out of the xz plane by this much y
        for (int axis = 0; axis < 3; ++axis) {
            const float eps = 1e-3f;
            const glm::vec3 below(std::sin(glm::radians(45.0f - eps)), tilt, std::cos(glm::radians(45.0f - eps)));
            const glm::vec3 above(std::sin(glm::radians(45.0f + eps)), tilt, std::cos(glm::radians(45.0f + eps)));
            EXPECT_NEAR(weightOn(below, axis), weightOn(above, axis), 1e-3f) << "tilt " << tilt << " axis " << axis;
        }
    }
    // The second and third axes swap: y and x equal, z dominant.
    for (int axis = 0; axis < 3; ++axis)
        EXPECT_NEAR(weightOn({0.3f + 1e-4f, 0.3f, 1.0f}, axis), weightOn({0.3f, 0.3f + 1e-4f, 1.0f}, axis), 1e-3f);
}

TEST(Sweeps, BlurWeightsSumToOne) {
    for (int n : {1, 2, 5, 9, 17, 32})
        for (BlurPhase phase : {BlurPhase::Phong, BlurPhase::HenyeyGreenstein}) {
            Indirect in;
            in.samples = n;
            in.phase = phase;
            in.angle = 40.0f;
            const auto taps = blurTaps(in);
            ASSERT_EQ(int(taps.size()), n);
            double sum = 0.0;
            for (const auto& t : taps) {
                sum += t.z;
                EXPECT_LE(glm::length(glm::vec2(t)), 1.0f + 1e-6f);
                EXPECT_GT(t.z, 0.0f);
            }
            EXPECT_NEAR(sum, 1.0, 1e-6) << n << " taps";
            EXPECT_EQ(glm::vec2(taps[0]), glm::vec2(0.0f));   // the centre: the light's own direction
            // Forward-peaked lobes weight the centre most.
            for (const auto& t : taps) EXPECT_LE(t.z, taps[0].z + 1e-7f);
        }
}

// The direct luminance of a homogeneous cube: exp(-sigma d) for depth d along the light. Along
// an axis, a face diagonal and the body diagonal every read lands on a cell centre and the
// trapezoid rule is exact for piecewise-constant cells, so only float rounding remains (40
// slices: < 2e-5 everywhere). At a generic angle the reads are exact in uniform slices (the
// domain-of-dependence cone under the top face). Where the light entered through a side face
// the transmittance varies sideways as exp(-sigma x / sin(theta)), and each bilinear read of a
// convex function overshoots by up to (sigma h / sin(theta))^2 / 8 (2.6e-3 here, h = 1 cell,
// sin(theta) = 0.55 sideways); summed over the slices between the side face and the cell this
// stays below 0.05 (measured 0.040 at sigma h = 0.08). The blended second axis takes long steps
// across the cube's edges; its share (here 1/4) keeps the cone within 2%.
void expectSlabMatches(KernelBackend& backend) {
    const float sigma = 0.08f;
    for (glm::vec3 dir : {glm::vec3(0, -1, 0), glm::vec3(1, -1, 0), glm::vec3(-1, -1, 1), glm::vec3(0.35f, -1, 0.2f)}) {
        for (bool blend : {false, true}) {
            auto lit = illuminate(slab(sigma), slabScene(dir, blend), backend);
            const SlabError e = slabError(lit->stage.volume(), sigma, dir);
            const bool exact = std::abs(dir.x) == std::abs(dir.y) || dir.x == 0.0f;
            SCOPED_TRACE("dir " + std::to_string(dir.x) + " " + std::to_string(dir.y) + " " + std::to_string(dir.z) +
                         (blend ? " blended" : " one axis"));
            EXPECT_LT(e.cone, exact || !blend ? 2e-5f : 0.02f);
            EXPECT_LT(e.envelope, exact ? 2e-5f : 0.05f);
        }
    }
}

TEST(Propagation, HomogeneousSlabGivesBeerLambertOnCpu) {
    auto cpu = makeCpuBackend();
    expectSlabMatches(*cpu);
}

TEST(Propagation, HomogeneousSlabGivesBeerLambertOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    expectSlabMatches(*gl);
}

// Resolution independence: the same slab on a grid of half the cells gives the same luminance
// at the same world points (every other cell centre of the fine grid is not a coarse centre, so
// compare the coarse cells with the analytic value instead).
TEST(Propagation, OpticalDepthIsIndependentOfTheGridResolution) {
    auto cpu = makeCpuBackend();
    const float sigma = 0.08f;
    Scene scene = slabScene({0, -1, 0}, false);
    scene.effects.light_resolution = kSlabGrid / 2;
    auto lit = illuminate(slab(sigma), scene, *cpu);
    const IlluminationVolume& v = lit->stage.volume();
    ASSERT_EQ(v.dims, glm::ivec3(kSlabGrid / 2));
    int checked = 0;
    for (int y = 0; y < v.dims.y; ++y) {
        const glm::vec3 c = cellCentre(v, {10, y, 10});
        if (!insideCube(c, 1.0f)) continue;   // coarse cells straddling the cube's face are half empty
        EXPECT_NEAR(luminanceAt(v, {10, y, 10}), std::exp(-sigma * (kSlab - 0.5f - c.y)), 2e-5f) << y;
        ++checked;
    }
    EXPECT_GE(checked, 14);
}

// Kniss 2003: blur weights sum to 1, so with transport colour 1 (no indirect attenuation) the
// light in a slice is only moved, never made or lost. A blob of light in a slice (none enters
// from outside: the light is black) spreads as it is swept but its total stays the same.
TEST(Propagation, IndirectEnergyPerSliceIsConserved) {
    const glm::ivec3 dims(40, 40, 24);
    std::vector<float> sigma(size_t(dims.x) * dims.y * dims.z, 0.3f);
    kernel::CpuKernel k;
    k.Q.grid_to_world = glm::mat4(1.0f);
    k.Q.world_to_grid = glm::mat4(1.0f);
    k.Q.dims = glm::ivec4(dims, 3);
    Indirect in;
    in.samples = 17;
    in.angle = 50.0f;
    const auto taps = blurTaps(in);
    for (size_t i = 0; i < taps.size(); ++i) k.Q.taps[i] = taps[i];
    k.Q.slice = glm::ivec4(2, 1, 0, int(taps.size()));
    k.Q.source = glm::vec4(0.1f, -0.05f, 1.0f, 0.0f);      // oblique: reads fall between centres
    k.Q.flow = glm::vec4(1.0f, std::tan(glm::radians(0.5f * in.angle)), 1.0f, 0.0f);
    k.Q.atten = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);          // transport colour 1
    k.Q.light.color = glm::vec4(0.0f);                        // nothing from outside
    k.prop_sigma = sigma.data();
    std::vector<float> prev(size_t(dims.x) * dims.y * 3, 0.0f), cur(prev.size());
    for (int j = 0; j < dims.y; ++j)
        for (int i = 0; i < dims.x; ++i) {
            const float r2 = float((i - 20) * (i - 20) + (j - 20) * (j - 20));
            for (int c = 0; c < 3; ++c) prev[(size_t(j) * dims.x + i) * 3 + c] = std::exp(-r2 / 8.0f) * float(c + 1);
        }
    auto total = [&](const std::vector<float>& s, int c) {
        double sum = 0.0;
        for (size_t i = size_t(c); i < s.size(); i += 3) sum += s[i];
        return sum;
    };
    auto spread = [&](const std::vector<float>& s) {   // mean squared distance from the blob's centre
        double m = 0.0, w = 0.0;
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const double v = s[(size_t(j) * dims.x + i) * 3];
                m += v * ((i - 20) * (i - 20) + (j - 20) * (j - 20));
                w += v;
            }
        return m / w;
    };
    const double start[3] = {total(prev, 0), total(prev, 1), total(prev, 2)};
    const double start_spread = spread(prev);
    for (int s = 1; s < 12; ++s) {
        k.Q.slice.z = s;
        k.prop_prev = prev.data();
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const glm::vec3 v = k.vx_prop_cell(i, j);
                for (int c = 0; c < 3; ++c) cur[(size_t(j) * dims.x + i) * 3 + c] = v[c];
            }
        std::swap(prev, cur);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(total(prev, c), start[c], 1e-5 * start[c]) << "slice " << s;
    }
    EXPECT_GT(spread(prev), start_spread + 5.0);   // and it did blur
}

// Kniss Fig. 9: a transport colour that keeps red best turns the indirect light orange, then red,
// with depth: the red / blue ratio grows monotonically down the slab.
TEST(Propagation, TransportColourShiftsIndirectLightWithDepth) {
    auto cpu = makeCpuBackend();
    Scene scene = slabScene({0, -1, 0}, false);
    Indirect in;
    in.transport_color = glm::vec3(1.0f, 0.6f, 0.3f);
    scene.effects.indirect = in;
    auto lit = illuminate(slab(0.1f), scene, *cpu);
    const IlluminationVolume& v = lit->stage.volume();
    ASSERT_EQ(v.chroma_dims, v.dims);
    float last = 0.0f;
    for (int y = v.dims.y - 1; y >= 0; --y) {
        const glm::vec3 centre = cellCentre(v, {24, y, 24});
        if (!insideCube(centre, 0.0f)) continue;
        const float* c = &v.values[v.indirectOffset() + ((size_t(24) * v.chroma_dims.y + y) * v.chroma_dims.x + 24) * 3];
        const float ratio = c[0] / c[2];
        EXPECT_GT(ratio, last) << "y " << y;
        // The ratio is the transport colour's: (1 / 0.3)^(optical depth).
        const float depth = float(kSlab) - 0.5f - centre.y;
        EXPECT_NEAR(std::log(ratio), -std::log(0.3f) * 0.1f * depth, 1e-3f * (1.0f + depth)) << y;
        last = ratio;
    }
}

}  // namespace
}  // namespace voxlux::test
