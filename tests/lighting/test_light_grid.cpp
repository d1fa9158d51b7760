// The light grid (Schlegel 2011's extinction grid, src/lighting/light_grid.cpp): the exact box
// filter of the voxels' piecewise-constant extinction, against brute force over every voxel of
// the occupied box, a cost that follows the occupied voxels rather than their box, and the
// colour-bleeding planes the SAT derives from the shared grid.
#include <algorithm>
#include <random>

#include "lighting/light_grid.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr float kDensityScale = 2.0f;   // extinction = grid value * density scale (no transfer function)

Scene gridScene() {
    Scene s;
    s.volume().material.density_scale = kDensityScale;
    return s;
}

// Values in [0, 1) with a third of the voxels empty, over index voxels [lo, lo + size).
openvdb::FloatGrid::Ptr randomGrid(openvdb::Coord lo, openvdb::Coord size, unsigned seed) {
    auto grid = boxGrid(lo, lo + size - openvdb::Coord(1), 0.0f);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    auto acc = grid->getAccessor();
    for (int z = 0; z < size.z(); ++z)
        for (int y = 0; y < size.y(); ++y)
            for (int x = 0; x < size.x(); ++x) {
                const float v = value(rng);
                acc.setValue(lo + openvdb::Coord(x, y, z), v < 0.33f ? 0.0f : v);
            }
    return grid;
}

// The mean extinction over cell `c`, from every voxel of the occupied box: voxel v (local to the
// box's first voxel) spans [v, v + 1), cell i spans [i * cell, min((i + 1) * cell, voxels)).
double bruteForceCell(const openvdb::FloatGrid& grid, const LightGrid& g, glm::ivec3 first_voxel, glm::ivec3 voxels,
                      glm::ivec3 c) {
    auto acc = grid.getConstAccessor();
    const auto overlap = [&](int axis, int v) {
        const double lo = c[axis] * double(g.cell), hi = std::min((c[axis] + 1) * double(g.cell), double(voxels[axis]));
        return std::max(std::min(double(v + 1), hi) - std::max(double(v), lo), 0.0);
    };
    double sum = 0;
    for (int z = 0; z < voxels.z; ++z)
        for (int y = 0; y < voxels.y; ++y)
            for (int x = 0; x < voxels.x; ++x) {
                const double w = overlap(0, x) * overlap(1, y) * overlap(2, z);
                if (w > 0) sum += w * kDensityScale * acc.getValue(openvdb::Coord(first_voxel.x + x, first_voxel.y + y, first_voxel.z + z));
            }
    return sum / (double(g.cell) * g.cell * g.cell);
}

TEST(LightGrid, IsTheExactBoxFilterOfTheVoxels) {
    // 21 x 13 x 9 voxels from (-5, 3, 7): bricks partly filled on every side.
    auto grid = randomGrid({-5, 3, 7}, {21, 13, 9}, 7);
    auto prepared = prepare(volumeFromGrid(grid), gridScene(), Camera{});
    const glm::ivec3 first_voxel = prepared->pages.bricks_min * VX_BRICK;
    const glm::ivec3 voxels = (prepared->pages.bricks_max - prepared->pages.bricks_min + 1) * VX_BRICK;
    // Cells of 6 voxels (larger than a brick), 3.43 (not a whole number) and 0.75 (smaller than a voxel).
    for (int resolution : {4, 7, 32}) {
        const LightGrid g = buildLightGrid(prepared->inputs, resolution);
        double worst = 0, peak = 0;
        for (int z = 0; z < g.dims.z; ++z)
            for (int y = 0; y < g.dims.y; ++y)
                for (int x = 0; x < g.dims.x; ++x) {
                    const double expected = bruteForceCell(*grid, g, first_voxel, voxels, {x, y, z});
                    const double got = g.values[(size_t(z) * g.dims.y + y) * g.dims.x + x];
                    worst = std::max(worst, std::abs(got - expected));
                    peak = std::max(peak, expected);
                }
        EXPECT_GT(peak, 0.1) << resolution;
        EXPECT_LE(worst, 1e-6 * peak) << "resolution " << resolution << ": largest difference " << worst;
    }
}

// The cells the light passes compute: every cell with extinction within one cell (its 3x3x3
// neighbourhood), against brute force over the neighbourhood.
TEST(LightGrid, NeededCellsAreTheExtinctionDilatedByOneCell) {
    auto prepared = prepare(volumeFromGrid(randomGrid({-5, 3, 7}, {21, 13, 9}, 13)), gridScene(), Camera{});
    const LightGrid g = buildLightGrid(prepared->inputs, 48);
    const glm::ivec3 d = g.dims;
    ASSERT_EQ(g.needed.size(), g.cells());
    auto index = [&](glm::ivec3 c) { return (size_t(c.z) * d.y + c.y) * d.x + c.x; };
    size_t needed = 0, empty = 0;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                bool expected = false;
                for (int k = 0; k < 27; ++k) {
                    const glm::ivec3 c = glm::ivec3(x, y, z) + glm::ivec3(k % 3, k / 3 % 3, k / 9) - 1;
                    if (glm::all(glm::greaterThanEqual(c, glm::ivec3(0))) && glm::all(glm::lessThan(c, d)))
                        expected |= g.values[index(c)] > 0.0f;
                }
                ASSERT_EQ(g.needed[index({x, y, z})], expected ? 1 : 0) << x << ", " << y << ", " << z;
                needed += expected;
                empty += g.values[index({x, y, z})] == 0.0f;
            }
    // Both kinds occur: needed cells without extinction, and cells left out.
    EXPECT_GT(needed + empty, g.cells());
    EXPECT_LT(needed, g.cells());
}

// The SAT's colour-bleeding planes for a material of one albedo, derived from the shared
// extinction grid, are the planes the box filter gives when it walks the voxels for them, to the
// float rounding of one product.
TEST(LightGrid, UniformBleedingPlanesAreTheBoxFilteredOnes) {
    Scene scene = gridScene();
    scene.volume().material.albedo = glm::vec3(0.9f, 0.6f, 0.3f);
    auto prepared = prepare(volumeFromGrid(randomGrid({-5, 3, 7}, {21, 13, 9}, 11)), scene, Camera{});
    ASSERT_TRUE(uniformAlbedo(prepared->inputs));
    const float bleeding = 0.7f;
    const LightGrid walked = buildLightGrid(prepared->inputs, 7, {true, bleeding});
    const LightGrid derived = withUniformBleeding(buildLightGrid(prepared->inputs, 7), scene.volume().material.albedo, bleeding);
    ASSERT_EQ(walked.planes, 4);
    ASSERT_EQ(derived.planes, 4);
    ASSERT_EQ(derived.values.size(), walked.values.size());
    const size_t plane = walked.cells();
    for (size_t p = 0; p < 4; ++p)
        for (size_t i = 0; i < plane; ++i) {
            const float a = walked.values[p * plane + i], b = derived.values[p * plane + i];
            ASSERT_LE(std::abs(a - b), 2.5e-7f * std::abs(a)) << "plane " << p << " cell " << i;
        }
    // Plane c is the extinction times 1 - 0.7 * albedo_c: 0.37, 0.58 and 0.79 of plane 0's.
    const size_t densest = size_t(std::max_element(walked.values.begin(), walked.values.begin() + plane) - walked.values.begin());
    EXPECT_GT(walked.values[densest], 0.5f);
    for (size_t c = 0; c < 3; ++c)
        EXPECT_NEAR(derived.values[(c + 1) * plane + densest] / derived.values[densest], 1.0f - bleeding * scene.volume().material.albedo[int(c)], 1e-6f) << c;
    EXPECT_EQ(derived.needed, walked.needed);
}

// Two boxes 200,000 voxels apart on every axis: the occupied box has 1.5e13 bricks, which a
// table over it would need 42 TB for. The grid's cost follows the 2 x 512 occupied voxels, and the
// filter keeps their extinction exactly: the cells' integral is the voxels' sum.
TEST(LightGrid, PartsFarApartCostWhatThePartsCost) {
    auto grid = boxGrid({0, 0, 0}, {7, 7, 7}, 0.5f);
    auto acc = grid->getAccessor();
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) acc.setValue(openvdb::Coord(200000 + x, 200000 + y, 200000 + z), 0.25f);
    auto prepared = prepare(volumeFromGrid(grid), gridScene(), Camera{});
    const LightGrid g = buildLightGrid(prepared->inputs, 64);
    double integral = 0;
    for (float v : g.values) integral += double(v) * g.cell * g.cell * g.cell;
    const double voxels_sum = 512 * (0.5 + 0.25) * kDensityScale;
    EXPECT_NEAR(integral, voxels_sum, 1e-6 * voxels_sum);
    EXPECT_EQ(std::count_if(g.values.begin(), g.values.end(), [](float v) { return v > 0; }), 2);
}

}  // namespace
}  // namespace voxlux::test
