// The extinction SAT and its queries (src/lighting/extinction_sat/kernel/vx_sat.h) against brute force and closed forms:
// exact box sums on adversarial grids, AO shells in empty and homogeneous media, cone shadows
// through slabs and from lights inside the volume.
#include <cmath>
#include <random>

#include "lighting/extinction_sat/kernel/cpu_sat_kernel.h"
#include "lighting/extinction_sat/summed_volume.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// A light grid of given cells, its SAT and a kernel bound to it. Cells are `cell_world` wide.
struct SatGrid {
    LightGrid grid;
    SummedVolume sat;
    kernel::CpuSatKernel k;

    SatGrid(glm::ivec3 dims, std::vector<float> values, float cell_world = 1.0f) {
        grid.dims = dims;
        grid.values = std::move(values);
        grid.needed.assign(grid.cells(), 1);
        buildSummedVolume(grid, sat);
        k.sat = sat.words;
        k.S.dims = dims;
        k.S.planes = 1;
        k.S.quantum = sat.quantum;
        k.S.light_to_world = glm::mat4(cell_world);
        k.S.light_to_world[3].w = 1.0f;
        k.S.world_to_light = glm::inverse(k.S.light_to_world);
    }
    SatGrid(const SatGrid&) = delete;

    size_t index(int x, int y, int z) const { return (size_t(z) * grid.dims.y + y) * grid.dims.x + x; }

    double bruteForce(glm::ivec3 lo, glm::ivec3 hi) const {
        double sum = 0.0;
        for (int z = lo.z; z < hi.z; ++z)
            for (int y = lo.y; y < hi.y; ++y)
                for (int x = lo.x; x < hi.x; ++x) sum += grid.values[index(x, y, z)];
        return sum;
    }
};

// Log-uniform values in [1e-6, 1e3]: twelve orders of magnitude between neighbours.
std::vector<float> spanningValues(glm::ivec3 d, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> exponent(-6.0f, 3.0f);
    std::vector<float> v(size_t(d.x) * d.y * d.z);
    for (auto& x : v) x = std::pow(10.0f, exponent(rng));
    return v;
}

// Boxes that stress the table: every single cell near the far corner (small differences of the
// largest prefix sums), the whole grid, slabs, and random boxes of every size.
std::vector<std::pair<glm::ivec3, glm::ivec3>> testBoxes(glm::ivec3 d, int random_boxes, int max_random_edge) {
    std::vector<std::pair<glm::ivec3, glm::ivec3>> boxes;
    for (int z = d.z - 3; z < d.z; ++z)
        for (int y = d.y - 3; y < d.y; ++y)
            for (int x = d.x - 3; x < d.x; ++x) boxes.push_back({{x, y, z}, {x + 1, y + 1, z + 1}});
    boxes.push_back({{0, 0, 0}, d});
    boxes.push_back({{0, 0, d.z - 1}, d});
    boxes.push_back({{d.x - 1, 0, 0}, d});
    boxes.push_back({{0, 0, 0}, {1, 1, 1}});
    std::mt19937 rng(7);
    for (int i = 0; i < random_boxes; ++i) {
        glm::ivec3 lo(0), hi(0);
        for (int a = 0; a < 3; ++a) {
            std::uniform_int_distribution<int> edge(1, std::min(max_random_edge, d[a]));
            const int e = edge(rng);
            lo[a] = std::uniform_int_distribution<int>(0, d[a] - e)(rng);
            hi[a] = lo[a] + e;
        }
        boxes.push_back({lo, hi});
    }
    return boxes;
}

// The bound: every box sum within 1e-6 of the brute-force double sum, relative.
void expectExactBoxes(const SatGrid& g, int random_boxes, int max_edge) {
    kernel::CpuSatKernel k = g.k;
    double worst = 0.0;
    for (const auto& [lo, hi] : testBoxes(g.grid.dims, random_boxes, max_edge)) {
        const double exact = g.bruteForce(lo, hi);
        const double got = k.vx_sat_weighted_box(0, 1.0f, lo, hi);
        const double rel = std::abs(got - exact) / exact;
        worst = std::max(worst, rel);
        ASSERT_LE(rel, 1e-6) << "box [" << lo.x << "," << lo.y << "," << lo.z << ") - [" << hi.x << "," << hi.y << ","
                             << hi.z << "): SAT " << got << " brute force " << exact;
    }
    std::cout << "  worst relative box-sum error " << worst << "\n";
}

TEST(Sat, BoxSumsExactOnSpanningValues64) {
    const glm::ivec3 d(64);
    SatGrid g(d, spanningValues(d, 1));
    expectExactBoxes(g, 20000, 64);
}

TEST(Sat, FloatPrefixSumsWouldFailTheSameBound) {
    // The check above can fail: the paper's float32 SAT misses the far-corner cells badly.
    const glm::ivec3 d(64);
    const auto v = spanningValues(d, 1);
    std::vector<float> s((d.x + 1) * (d.y + 1) * (d.z + 1), 0.0f);
    auto at = [&](int x, int y, int z) -> float& { return s[(size_t(z) * (d.y + 1) + y) * (d.x + 1) + x]; };
    for (int z = 1; z <= d.z; ++z)
        for (int y = 1; y <= d.y; ++y)
            for (int x = 1; x <= d.x; ++x)
                at(x, y, z) = v[(size_t(z - 1) * d.y + (y - 1)) * d.x + (x - 1)] + at(x - 1, y, z) + at(x, y - 1, z) +
                              at(x, y, z - 1) - at(x - 1, y - 1, z) - at(x - 1, y, z - 1) - at(x, y - 1, z - 1) +
                              at(x - 1, y - 1, z - 1);
    const int n = d.x;
    const double box = double(at(n, n, n)) - at(n - 1, n, n) - at(n, n - 1, n) - at(n, n, n - 1) +
                       at(n - 1, n - 1, n) + at(n - 1, n, n - 1) + at(n, n - 1, n - 1) - at(n - 1, n - 1, n - 1);
    const double exact = v.back();
    EXPECT_GT(std::abs(box - exact) / exact, 1e-3) << "float SAT " << box << " exact " << exact;
}

TEST(Sat, BoxSumsExactOnConstantGrid64) {
    const glm::ivec3 d(64);
    SatGrid g(d, std::vector<float>(size_t(d.x) * d.y * d.z, 1e3f));
    expectExactBoxes(g, 5000, 64);
}

// Rows far wider than the build's column blocks (its y pass keeps 64 columns' sums at a time), so
// that the sanitizer run, which leaves out the 512^3 case, covers rows of many blocks.
TEST(Sat, BoxSumsExactOnAWideGrid) {
    const glm::ivec3 d(1000, 6, 5);
    SatGrid g(d, spanningValues(d, 3));
    expectExactBoxes(g, 5000, 1000);
}

TEST(Sat, BoxSumsExactOn512Cubed) {
    const glm::ivec3 d(512);
    {
        SatGrid g(d, spanningValues(d, 2));
        expectExactBoxes(g, 300, 96);
    }
    SatGrid g(d, std::vector<float>(size_t(d.x) * d.y * d.z, 1e3f));
    expectExactBoxes(g, 100, 96);
}

TEST(Sat, QuantumIsAPowerOfTwoAboveTheMaximum) {
    EXPECT_EQ(satQuantum(1000.0f), std::ldexp(1.0f, 10 - 63));   // 2^10 > 1000
    EXPECT_EQ(satQuantum(1024.0f), std::ldexp(1.0f, 11 - 63));   // strictly above
    EXPECT_EQ(satQuantum(0.0f), 1.0f);
    EXPECT_EQ(satQuantum(1e-30f), std::ldexp(1.0f, -60 - 63));   // stays a normal float
}

// AO shells: half-widths k_i = floor(i R / n).
std::vector<int> shellHalfWidths(int n, float radius_cells) {
    std::vector<int> k;
    for (int i = 1; i <= n; ++i) k.push_back(int(std::floor(i * radius_cells / n)));
    return k;
}

void setShells(kernel::CpuSatKernel& k, int shells, float radius_cells, float cell_world) {
    k.S.shells = shells;
    k.S.shell_radius = radius_cells;
    k.S.cell_world = cell_world;
}

TEST(AmbientOcclusion, EmptyNeighbourhoodIsExactlyOne) {
    const glm::ivec3 d(40);
    std::vector<float> v(size_t(d.x) * d.y * d.z, 0.0f);
    v[0] = 50.0f;  // far from the cell below
    SatGrid g(d, v);
    kernel::CpuSatKernel k = g.k;
    setShells(k, 5, 8.0f, 1.0f);
    const float tau = k.vx_ambient_tau({30, 30, 30}, 0);
    EXPECT_EQ(tau, 0.0f);
    EXPECT_EQ(k.vx_exp(-tau), 1.0f);
    EXPECT_GT(k.vx_ambient_tau({3, 3, 3}, 0), 0.0f);  // within reach of the dense cell
}

TEST(AmbientOcclusion, HomogeneousMediumMatchesTheShellSum) {
    const glm::ivec3 d(48);
    const float sigma = 0.3f, cell = 0.25f;
    SatGrid g(d, std::vector<float>(size_t(d.x) * d.y * d.z, sigma), cell);
    for (int shells : {1, 3, 7, 11, 40}) {  // 40 > radius: repeated cubes
        kernel::CpuSatKernel k = g.k;
        const float radius = 12.0f;
        setShells(k, shells, radius, cell);
        double expected = 0.0, inner = 0.0;
        for (int h : shellHalfWidths(shells, radius)) {  // Eq. 4 shell by shell
            const double outer = std::pow(2.0 * h + 1.0, 3.0) * sigma;
            expected += (outer - inner) / ((h + 0.5) * (h + 0.5));
            inner = outer;
        }
        expected *= cell / 24.0;
        EXPECT_NEAR(k.vx_ambient_tau({24, 24, 24}, 0), expected, 1e-6 * expected) << shells << " shells";
    }
}

// With a shell per ring of cells, the homogeneous AO approaches the optical depth to the edge,
// sigma * R. Weighting each ring by its outer radius (as the paper does) undercounts the inner
// rings: sum_k (24k^2 + 2) / (k + 1/2)^2 falls short of 24 (R + 1/2) by about 24 (ln R + 1), a
// relative deficit below (ln R + 1.5) / R.
TEST(AmbientOcclusion, ManyShellsGiveTheOpticalDepthToTheEdge) {
    const glm::ivec3 d(64);
    const float sigma = 0.4f, cell = 0.5f, radius = 24.0f;
    SatGrid g(d, std::vector<float>(size_t(d.x) * d.y * d.z, sigma), cell);
    kernel::CpuSatKernel k = g.k;
    setShells(k, 96, radius, cell);
    const double edge = sigma * (radius + 0.5) * cell;  // the outermost cube's inscribed radius
    const double ratio = k.vx_ambient_tau({32, 32, 32}, 0) / edge;
    EXPECT_LE(ratio, 1.0);
    EXPECT_GE(ratio, 1.0 - (std::log(radius) + 1.5) / radius);
}

TEST(AmbientOcclusion, MonotoneInDensity) {
    const glm::ivec3 d(32);
    auto base = spanningValues(d, 3);
    std::vector<float> denser = base;
    std::mt19937 rng(4);
    for (auto& x : denser) x *= 1.0f + std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
    SatGrid a(d, base), b(d, denser);
    kernel::CpuSatKernel ka = a.k, kb = b.k;
    setShells(ka, 3, 6.0f, 1.0f);
    setShells(kb, 3, 6.0f, 1.0f);
    for (int z = 0; z < d.z; z += 3)
        for (int y = 0; y < d.y; y += 3)
            for (int x = 0; x < d.x; x += 3)
                ASSERT_GE(kb.vx_ambient_tau({x, y, z}, 0), ka.vx_ambient_tau({x, y, z}, 0)) << x << "," << y << "," << z;
}

kernel::VxLight directional(glm::vec3 travel) {
    kernel::VxLight l{};
    l.type = VX_LIGHT_DIRECTIONAL;
    l.direction = glm::normalize(travel);
    return l;
}

kernel::VxLight point(glm::vec3 position) {
    kernel::VxLight l{};
    l.position = position;
    l.type = VX_LIGHT_POINT;
    return l;
}

void setCone(kernel::CpuSatKernel& k, float angle_deg, int samples, float growth) {
    k.S.cone_tan = std::tan(glm::radians(angle_deg));
    k.S.cone_cuboids = samples;
    k.S.cone_growth = growth;
    k.S.cone_growth_total = std::pow(1.0f + growth, float(samples));
}

// A slab of extinction sigma filling cells z in [z0, z1) of a grid, empty elsewhere.
std::vector<float> slab(glm::ivec3 d, int z0, int z1, float sigma) {
    std::vector<float> v(size_t(d.x) * d.y * d.z, 0.0f);
    for (int z = z0; z < z1; ++z)
        std::fill(v.begin() + size_t(z) * d.x * d.y, v.begin() + size_t(z + 1) * d.x * d.y, sigma);
    return v;
}

// Light from above (+z) through a slab whose faces lie on cell faces. While the primary axis is
// the slab's normal, each cuboid's extent along it is exact and its cross-section sees a
// laterally uniform medium, so the cone sum is exact: tau = sigma * (distance to the top face
// along the ray), whatever the cone angle and cuboid count.
TEST(ConeShadow, SlabMatchesBeerLambertWhenThePrimaryAxisIsTheNormal) {
    const glm::ivec3 d(64, 64, 48);
    const float sigma = 0.2f, cell = 0.5f;
    SatGrid g(d, slab(d, 8, 40, sigma), cell);
    for (glm::vec3 travel : {glm::vec3(0, 0, -1), glm::vec3(0.3f, 0.2f, -1), glm::vec3(-0.6f, 0.5f, -1)})
        for (float angle : {0.0f, 1.0f, 4.0f})
            for (int samples : {12, 50}) {
                kernel::CpuSatKernel k = g.k;
                setCone(k, angle, samples, 0.05f);
                const glm::ivec3 c(32, 32, 20);
                const glm::vec3 to_light = -glm::normalize(travel);
                const double d_world = (40.0 - (c.z + 0.5)) * cell / to_light.z;  // inside the slab
                const double expected = std::exp(-sigma * d_world);
                const double got = std::exp(-double(k.vx_cone_tau(c, directional(travel))));
                EXPECT_NEAR(got, expected, 1e-5 * expected)
                    << "travel " << travel.x << "," << travel.y << " angle " << angle << " samples " << samples;
            }
}

// Grazing light (primary axis across the slab's normal): a cuboid's extent along the normal is
// the ray's rounded to cell faces, wrong by at most one cell at each of the slab's two faces the
// cone meets, so |tau - sigma d| <= 2 sigma * (cell along the ray) = 2 sigma cell |w| / |w_a|.
TEST(ConeShadow, GrazingSlabWithinTheCuboidBound) {
    const glm::ivec3 d(96, 32, 48);
    const float sigma = 0.2f, cell = 0.5f;
    SatGrid g(d, slab(d, 8, 40, sigma), cell);
    const glm::vec3 travel(-1.0f, 0.0f, -0.4f);  // primary axis x
    kernel::CpuSatKernel k = g.k;
    setCone(k, 0.0f, 50, 0.0f);
    const glm::vec3 w = -travel / std::abs(travel.x);
    const double bound = 2.0 * sigma * cell * glm::length(w);
    for (int z : {12, 20, 30}) {
        const glm::ivec3 c(20, 16, z);
        // Along the ray to the top face (z = 40), then empty; the x reach (to the grid face)
        // leaves the slab first if the face is nearer.
        const double dz = 40.0 - (z + 0.5), reach_x = d.x - (c.x + 0.5);
        const double t = std::min(dz / w.z, reach_x);  // primary-axis cells inside the slab
        const double expected = sigma * t * cell * glm::length(w);
        EXPECT_NEAR(k.vx_cone_tau(c, directional(travel)), expected, bound) << "z " << z;
    }
}

// A point light inside (or on the face of) a homogeneous cube: every cuboid lies in the medium,
// so tau = sigma * distance exactly, for cells in any direction from the light.
TEST(ConeShadow, PointLightInsideOrOnTheFaceOfAHomogeneousVolume) {
    const glm::ivec3 d(40);
    const float sigma = 0.5f, cell = 0.25f;
    SatGrid g(d, std::vector<float>(size_t(d.x) * d.y * d.z, sigma), cell);
    for (glm::vec3 light_cells : {glm::vec3(20.3f, 19.6f, 21.1f), glm::vec3(0.0f, 20.0f, 20.0f)}) {
        kernel::CpuSatKernel k = g.k;
        setCone(k, 1.0f, 20, 0.1f);
        const kernel::VxLight light = point(light_cells * cell);
        for (glm::ivec3 c : {glm::ivec3(5, 20, 20), glm::ivec3(33, 8, 30), glm::ivec3(20, 20, 20), glm::ivec3(1, 3, 36)}) {
            const double dist = glm::length(glm::vec3(c) + 0.5f - light_cells) * cell;
            EXPECT_NEAR(k.vx_cone_tau(c, light), sigma * dist, 1e-5 * (1.0 + sigma * dist))
                << "light " << light_cells.x << " cell " << c.x << "," << c.y << "," << c.z;
        }
    }
}

// Hard cases stay finite: a medium of extinction 1e4 (tau ~ 1e5) shadows completely, a light at
// a cell centre is unshadowed, and nothing produces NaN.
TEST(ConeShadow, DenseMediaAndDegenerateLightsStayFinite) {
    const glm::ivec3 d(24);
    SatGrid g(d, std::vector<float>(size_t(d.x) * d.y * d.z, 1e4f));
    kernel::CpuSatKernel k = g.k;
    setCone(k, 3.0f, 20, 0.05f);
    const float dense = k.vx_cone_tau({12, 12, 2}, directional({0, 0, -1}));
    EXPECT_TRUE(std::isfinite(dense));
    EXPECT_GT(dense, 1e4f);
    EXPECT_LT(k.vx_exp(-dense), 1e-37f);  // vx_exp's floor, e^-87
    EXPECT_EQ(k.vx_cone_tau({5, 5, 5}, point(glm::vec3(5.5f))), 0.0f);
    setShells(k, 11, 30.0f, 1.0f);
    EXPECT_TRUE(std::isfinite(k.vx_ambient_tau({0, 0, 0}, 0)));
}

}  // namespace
}  // namespace voxlux::test
