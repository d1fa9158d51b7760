// Bricking: exact round trip of real data, tiles expanded, memory that follows active voxels.
#include <unordered_map>

#include "kernel/cpu_kernel_data.h"
#include "core/error.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

struct BrickHash {
    size_t operator()(const glm::ivec3& b) const { return size_t(b.x) * 73856093u ^ size_t(b.y) * 19349663u ^ size_t(b.z) * 83492791u; }
};

// Every active voxel of `grid` (leaf voxels and tile voxels) must read back bit-exactly from
// the atlas, through the slot the kernel's page lookup returns. Bricks that are zero throughout
// are classified away, so a missing brick is right only for a zero voxel.
void expectRoundTrip(const openvdb::FloatGrid& grid, const BrickAtlas& atlas, const PageTable& pages) {
    kernel::CpuKernelData k;
    k.P.page_capacity = pages.brick_capacity;
    k.P.page_max_probe = pages.max_probe;
    k.P.bricks_min = pages.bricks_min;
    k.P.bricks_max = pages.bricks_max;
    k.page = pages.entries;
    size_t checked = 0, wrong = 0;
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        openvdb::CoordBBox box = it.getBoundingBox();
        for (auto c = box.begin(); c; ++c) {
            const glm::ivec3 v((*c).x(), (*c).y(), (*c).z());
            const glm::ivec3 b = v >> 3;
            const int slot = k.vx_page_lookup(b);
            if (slot == VX_PAGE_EMPTY) {
                ASSERT_EQ(*it, 0.0f) << "brick of voxel " << v.x << "," << v.y << "," << v.z << " missing";
                ++checked;
                continue;
            }
            const glm::ivec3 l = v - b * 8;
            const float stored = atlas.density[size_t(slot) * VX_BRICK_VOXELS + (l.z * 9 + l.y) * 9 + l.x];
            wrong += stored != *it;
            ++checked;
        }
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(checked, grid.activeVoxelCount());
}

TEST(Bricks, SmokeRoundTripIsExact) {
    VOXLUX_REQUIRE_SHARED(path, "arnold-usd/smoke.vdb");
    Scene scene;
    scene.volume().path = path;
    auto volume = loadVolume(path, scene.volume());
    BrickAtlas atlas = buildBrickAtlas(volume);
    PageTable pages = buildPageTable(atlas.coords, classifyBricks(atlas, scene.volume().material, scene.volume().emission));
    expectRoundTrip(*volume.density, atlas, pages);
    EXPECT_EQ(atlas.active_voxels, 1049275u);
}

TEST(Bricks, CloudTilesAreExpandedNotDropped) {
    VOXLUX_REQUIRE_SHARED(path, "disney-wdas-cloud/wdas_cloud_sixteenth.vdb");
    Scene scene;
    auto volume = loadVolume(path, scene.volume());
    ASSERT_GT(volume.density->tree().activeTileCount(), 0u);
    BrickAtlas atlas = buildBrickAtlas(volume);
    PageTable pages = buildPageTable(atlas.coords, classifyBricks(atlas, scene.volume().material, scene.volume().emission));
    expectRoundTrip(*volume.density, atlas, pages);
}

TEST(Bricks, ApronHoldsTheNextBricksFirstVoxels) {
    auto g = openvdb::FloatGrid::create(0.0f);
    auto acc = g->getAccessor();
    for (int i = 0; i < 24; ++i) acc.setValue({i, 2 * i % 17, (5 * i) % 19}, 1.0f + float(i));
    auto volume = volumeFromGrid(g);
    BrickAtlas atlas = buildBrickAtlas(volume);
    for (size_t s = 0; s < atlas.slots(); ++s) {
        const glm::ivec3 o = atlas.coords[s] * 8;
        for (int z = 0; z < 9; ++z)
            for (int y = 0; y < 9; ++y)
                for (int x = 0; x < 9; ++x)
                    ASSERT_EQ(atlas.density[s * VX_BRICK_VOXELS + (z * 9 + y) * 9 + x],
                              acc.getValue({o.x + x, o.y + y, o.z + z}));
    }
}

openvdb::FloatGrid::Ptr blob(openvdb::FloatGrid::Ptr g, openvdb::Coord centre, int radius) {
    auto acc = g->getAccessor();
    for (int z = -radius; z <= radius; ++z)
        for (int y = -radius; y <= radius; ++y)
            for (int x = -radius; x <= radius; ++x)
                if (x * x + y * y + z * z <= radius * radius) acc.setValue(centre.offsetBy(x, y, z), 0.5f);
    return g;
}

// Bytes of the atlas and page table, and the entries of the page table's regions' table.
std::pair<size_t, size_t> footprint(const openvdb::FloatGrid::Ptr& g) {
    auto volume = volumeFromGrid(g);
    BrickAtlas atlas = buildBrickAtlas(volume);
    PageTable pages = buildPageTable(atlas.coords, classifyBricks(atlas, Material{}, {}));
    return {atlas.bytes() + pages.entries.size() * sizeof(glm::ivec4), size_t(pages.region_capacity)};
}

TEST(Bricks, MemoryFollowsActiveVoxelsNotTheBoundingBox) {
    const auto [one, one_regions] = footprint(blob(openvdb::FloatGrid::create(0.0f), {0, 0, 0}, 20));
    auto two = blob(openvdb::FloatGrid::create(0.0f), {0, 0, 0}, 20);
    blob(two, {10000, 10000, 10000}, 20);  // 17,320 voxels apart along the diagonal
    const auto [both, both_regions] = footprint(two);
    // Two identical blobs: every brick and page-table entry doubles, and the only addition for the
    // 10,000 empty voxels between them (a dense box would need 4e12 bytes) is the regions' table,
    // of at most twice the 16 regions the blobs touch (each spans 2 regions an axis).
    EXPECT_EQ(one_regions, 0u);
    EXPECT_LE(both_regions, 32u);
    EXPECT_LE(both, 2 * one + both_regions * sizeof(glm::ivec4));
    EXPECT_GT(both, one);
}

// The regions' table (the march's coarse level): present only when most regions of the box hold
// no brick, and then it answers for exactly the regions that hold one, with their brick counts.
TEST(Bricks, RegionsTableListsTheOccupiedRegionsWhenSomeAreEmpty) {
    const auto pagesOf = [](const openvdb::FloatGrid::Ptr& grid) {
        BrickAtlas atlas = buildBrickAtlas(volumeFromGrid(grid));
        return buildPageTable(atlas.coords, classifyBricks(atlas, Material{}, {}));
    };
    // Two regions side by side (voxels 0-127 along x), both holding bricks: no table.
    const PageTable adjacent = pagesOf(boxGrid({0, 0, 0}, {127, 7, 7}, 1.0f));
    EXPECT_EQ(adjacent.region_capacity, 0);

    // Two parts far apart: every region of their box is checked against the bricks the page table
    // holds in it (their aprons make the bricks on their - sides visible too).
    auto grid = boxGrid({0, 0, 0}, {7, 7, 7}, 1.0f);
    grid->denseFill(openvdb::CoordBBox({-24, 0, 512}, {-1, 7, 519}), 1.0f, true);
    const PageTable parts = pagesOf(grid);
    ASSERT_GT(parts.region_capacity, 0);
    kernel::CpuKernelData k;
    k.P.page_capacity = parts.brick_capacity;
    k.P.page_max_probe = parts.max_probe;
    k.P.bricks_min = parts.bricks_min;
    k.P.bricks_max = parts.bricks_max;
    k.P.region_capacity = parts.region_capacity;
    k.P.region_max_probe = parts.region_max_probe;
    k.page = parts.entries;
    EXPECT_EQ(kernel::vx_region_of(glm::ivec3(-3, 0, 64)), glm::ivec3(-1, 0, 8));  // floor(-3 / 8) = -1
    const glm::ivec3 lo = kernel::vx_region_of(parts.bricks_min), hi = kernel::vx_region_of(parts.bricks_max);
    int occupied = 0, empty = 0;
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                int bricks = 0;
                for (int bz = 0; bz < 8; ++bz)
                    for (int by = 0; by < 8; ++by)
                        for (int bx = 0; bx < 8; ++bx)
                            bricks += k.vx_page_lookup(glm::ivec3(x, y, z) * 8 + glm::ivec3(bx, by, bz)) != VX_PAGE_EMPTY;
                const int found = k.vx_table_find({x, y, z}, parts.brick_capacity, parts.region_capacity, parts.region_max_probe);
                EXPECT_EQ(found, bricks ? bricks : VX_PAGE_EMPTY) << "region " << x << ", " << y << ", " << z;
                EXPECT_EQ(k.vx_region_occupied({x, y, z}), bricks > 0);
                (bricks ? occupied : empty) += 1;
            }
    EXPECT_GE(occupied, 2);
    EXPECT_GE(empty, 14);  // the regions between the parts (z = 1 to 7)
}

TEST(Bricks, EmptyGridGivesAnEmptyPageTable) {
    auto volume = volumeFromGrid(openvdb::FloatGrid::create(0.0f));
    BrickAtlas atlas = buildBrickAtlas(volume);
    PageTable pages = buildPageTable(atlas.coords, classifyBricks(atlas, Material{}, {}));
    EXPECT_EQ(atlas.slots(), 0u);
    EXPECT_TRUE(pages.empty());
}

TEST(Bricks, TransferFunctionClassifiesTransparentBricksAway) {
    auto g = boxGrid({0, 0, 0}, {7, 7, 7}, 0.2f);
    g->denseFill(openvdb::CoordBBox({64, 0, 0}, {71, 7, 7}), 0.8f, true);
    auto volume = volumeFromGrid(g);
    BrickAtlas atlas = buildBrickAtlas(volume);
    Material m;
    m.transfer = {{0.0f, 0.0f, glm::vec3(1)}, {0.5f, 0.0f, glm::vec3(1)}, {1.0f, 1.0f, glm::vec3(1)}};
    PageTable pages = buildPageTable(atlas.coords, classifyBricks(atlas, m, {}));
    // Only the 0.8 block (brick 8) and its - side neighbours whose aprons reach it stay.
    EXPECT_EQ(pages.bricks_min.x, 7);
    EXPECT_EQ(pages.bricks_max.x, 8);
}

}  // namespace
}  // namespace voxlux::test

namespace voxlux::test {
namespace {

TEST(Bricks, HugeActiveTilesAreRefusedNotDensified) {
    auto g = openvdb::FloatGrid::create(0.0f);
    g->tree().addTile(3, openvdb::Coord(0), 1.0f, true);  // a root tile: 4096^3 voxels, 512^3 bricks
    auto volume = volumeFromGrid(g);
    volume.file = "hostile.vdb";
    try {
        buildBrickAtlas(volume);
        FAIL() << "a 4096^3 tile was densified";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "hostile.vdb: active tiles expand to more than 4194304 bricks of 8^3 voxels; refusing to densify");
    }
}

TEST(Bricks, ModerateTilesAreExpanded) {
    auto g = openvdb::FloatGrid::create(0.0f);
    g->tree().addTile(2, openvdb::Coord(0), 0.25f, true);  // 128^3 voxels in one tile
    auto volume = volumeFromGrid(g);
    BrickAtlas atlas = buildBrickAtlas(volume);
    PageTable pages = buildPageTable(atlas.coords, classifyBricks(atlas, Material{}, {}));
    EXPECT_EQ(pages.bricks_min, glm::ivec3(-1));  // - side neighbours hold the ramp into the tile
    EXPECT_EQ(pages.bricks_max, glm::ivec3(15));
    expectRoundTrip(*g, atlas, pages);
}

}  // namespace
}  // namespace voxlux::test

namespace voxlux::test {
namespace {

// Emission grids often come at another resolution than density: they are resampled onto the
// density grid's index space, with a warning, so one page table serves both.
TEST(Load, EmissionOnAnotherTransformIsResampled) {
    auto density = boxGrid({0, 0, 0}, {15, 15, 15}, 0.3f, 1.0);
    auto heat = boxGrid({0, 0, 0}, {31, 31, 31}, 2.0f, 0.5);  // the same 16-unit cube, finer
    heat->setName("heat");
    const std::string file = tempDir("load") + "/two_resolutions.vdb";
    openvdb::io::File(file).write({density, heat});
    VolumeSpec spec;
    spec.emission.resize(1);
    spec.emission[0].grid = GridRef{"heat", 0};
    LoadedVolume v = loadVolume(file, spec);
    ASSERT_EQ(v.warnings.size(), 1u);
    EXPECT_EQ(v.warnings[0], file + ": grid 'heat' has a different transform from 'density'; resampled onto it");
    ASSERT_EQ(v.emission.size(), 1u);
    EXPECT_EQ(v.emission[0]->transform(), v.density->transform());
    EXPECT_NEAR(v.emission[0]->tree().getValue(openvdb::Coord(8, 8, 8)), 2.0f, 1e-5f);
    BrickAtlas atlas = buildBrickAtlas(v);
    EXPECT_NEAR(atlas.emissionGridMax(0), 2.0f, 1e-5f);
}

}  // namespace
}  // namespace voxlux::test
