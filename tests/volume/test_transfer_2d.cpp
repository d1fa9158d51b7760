// The two-dimensional transfer function (material.transfer_function_2d): which voxels a region in
// the value x gradient-magnitude plane selects, what the render makes of them, and what an edit
// of the regions recomputes.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "backend/backend_choice.h"
#include "optics/transfer_function_2d.h"
#include "optics/transfer_presets.h"
#include "scene/scene_json.h"
#include "render/renderer.h"
#include "test_support.h"
#include "volume/transfer_2d.h"

namespace voxlux::test {
namespace {

TEST(Transfer2d, RegionWeightsRampOverTheirFade) {
    TransferRegion box;
    box.value = {0.0f, 100.0f};
    box.gradient = {0.0f, 10.0f};
    EXPECT_EQ(regionWeight(box, {50.0f, 5.0f}), 1.0f);
    EXPECT_EQ(regionWeight(box, {100.5f, 5.0f}), 0.0f);
    EXPECT_EQ(regionWeight(box, {50.0f, 10.5f}), 0.0f);
    box.fade = 0.5f;   // full from halfway to the centre: 25..75 in value, 2.5..7.5 in gradient
    EXPECT_NEAR(regionWeight(box, {10.0f, 5.0f}), 0.4f, 1e-6f);   // a fifth of the way in along the value: 0.2 / 0.5
    EXPECT_NEAR(regionWeight(box, {50.0f, 9.5f}), 0.2f, 1e-6f);   // a tenth of the way in along the gradient
    EXPECT_EQ(regionWeight(box, {30.0f, 4.0f}), 1.0f);
    EXPECT_EQ(regionWeight(box, {30.0f, 0.0f}), 1.0f);   // the gradient's range starts at 0: no fade there
    box.gradient = {1.0f, 11.0f};
    EXPECT_NEAR(regionWeight(box, {30.0f, 1.5f}), 0.2f, 1e-6f);   // from 1 it fades at both ends
    box.gradient = {0.0f, 10.0f};

    TransferRegion tri;
    tri.triangle = true;
    tri.corners = {glm::vec2(50.0f, 0.0f), glm::vec2(20.0f, 30.0f), glm::vec2(80.0f, 30.0f)};   // Kniss's boundary widget
    EXPECT_EQ(regionWeight(tri, {50.0f, 15.0f}), 1.0f);
    EXPECT_EQ(regionWeight(tri, {30.0f, 5.0f}), 0.0f);   // low gradient far from the apex's value: outside
    tri.fade = 1.0f;
    EXPECT_NEAR(regionWeight(tri, {50.0f, 20.0f}), 1.0f, 1e-5f);   // the centroid
    EXPECT_NEAR(regionWeight(tri, {50.0f, 30.0f}), 0.0f, 1e-5f);   // on the top edge

    // Overlapping regions: extinctions add, the albedo is their extinction-weighted mean.
    box.fade = 0.0f;
    box.extinction = 1.0f;
    box.albedo = glm::vec3(1.0f, 0.0f, 0.0f);
    TransferRegion other = box;
    other.extinction = 3.0f;
    other.albedo = glm::vec3(0.0f, 0.0f, 1.0f);
    const Classified c = classify2d({box, other}, 50.0f, 5.0f);
    EXPECT_EQ(c.extinction, 4.0f);
    EXPECT_EQ(c.albedo, glm::vec3(0.25f, 0.0f, 0.75f));
}

// value = 1000 - r^2 (r in world units) has the gradient magnitude 2r, which central differences
// give exactly (they are exact on quadratics), on voxels of three different edges. A region
// selecting gradients in [2a, 2b] selects exactly the voxels whose centres lie in the shell a..b.
TEST(Transfer2d, AGradientBandSelectsExactlyItsShellOfASphere) {
    initOpenVdb();
    const glm::dvec3 edge(0.5, 0.75, 1.0);
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(
        openvdb::math::Mat4d(edge.x, 0.0, 0.0, 0.0, 0.0, edge.y, 0.0, 0.0, 0.0, 0.0, edge.z, 0.0, 0.0, 0.0, 0.0, 1.0)));
    const openvdb::Coord lo(-16, -11, -8), hi(16, 11, 8);   // +-8 world units along each axis
    const auto radius = [&](const openvdb::Coord& c) { return glm::length(glm::dvec3(c.x(), c.y(), c.z()) * edge); };
    auto acc = grid->getAccessor();
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) {
                const double r = radius({x, y, z});
                acc.setValueOn({x, y, z}, float(1000.0 - r * r));
            }
    const double a = 2.3, b = 5.3;
    TransferRegion shell;
    shell.value = {900.0f, 1001.0f};   // excludes the background outside the box
    shell.gradient = {float(2 * a), float(2 * b)};
    shell.extinction = 2.5f;
    shell.albedo = glm::vec3(0.2f, 0.4f, 0.8f);

    std::vector<std::string> warnings;
    const LoadedVolume out = applyTransfer2d(volumeFromGrid(grid), {shell}, warnings);
    EXPECT_TRUE(warnings.empty());
    size_t expected = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        const double r = radius(it.getCoord());
        ASSERT_GT(std::min(std::abs(r - a), std::abs(r - b)), 1e-3) << "a voxel centre on the band's edge: the test is ambiguous";
        expected += r >= a && r <= b;
    }
    EXPECT_GT(expected, 1000u);
    EXPECT_EQ(out.density->activeVoxelCount(), expected);
    auto colour = out.color->getConstAccessor();
    for (auto it = out.density->cbeginValueOn(); it; ++it) {
        const double r = radius(it.getCoord());
        ASSERT_TRUE(r >= a && r <= b) << "r " << r;
        ASSERT_EQ(*it, 2.5f);
        ASSERT_EQ(colour.getValue(it.getCoord()), openvdb::Vec3s(0.2f, 0.4f, 0.8f));
    }
}

// On data that takes only the values 0 and 100, a 1D function linear over [0, 100] and a 2D
// region selecting value 100 give the same extinction and albedo everywhere after interpolation
// (the 1D function classifies after it, the 2D before it): the same image.
TEST(Transfer2d, MatchesAnEquivalentOneDimensionalFunction) {
    initOpenVdb();
    auto cpu = makeCpuBackend();
    auto grid = boxGrid({-10, -6, -8}, {10, 6, 8}, 100.0f, 0.1);
    auto hole = grid->getAccessor();
    for (int z = -3; z <= 3; ++z)
        for (int y = -2; y <= 2; ++y)
            for (int x = -4; x <= 1; ++x) hole.setValueOff({x, y, z}, 0.0f);   // a cavity, so that there are edges inside
    Scene one;
    one.camera = cameraAlong(glm::vec3(0.0f), glm::normalize(glm::vec3(-0.4f, -0.3f, -1.0f)), 4.0f, 40.0f);
    one.render.width = one.render.height = 48;
    one.lights = {Light{}};
    one.lights[0].direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.3f));
    one.lights[0].intensity = 4.0f;
    one.volume().material.albedo = glm::vec3(0.9f);
    one.volume().material.transfer = {TransferPoint{0.0f, 0.0f, glm::vec3(0.5f, 0.8f, 1.0f)}, TransferPoint{100.0f, 3.0f, glm::vec3(0.5f, 0.8f, 1.0f)}};
    Scene two = one;
    two.volume().material.transfer.clear();
    TransferRegion region;
    region.value = {50.0f, 150.0f};
    region.extinction = 3.0f;
    region.albedo = glm::vec3(0.5f, 0.8f, 1.0f);
    two.volume().material.transfer_2d = {region};
    for (ShadowMethod shadows : {ShadowMethod::Raymarch, ShadowMethod::Propagation}) {
        one.effects.shadows = two.effects.shadows = shadows;
        Renderer r1(one, volumeFromGrid(grid), *cpu), r2(two, volumeFromGrid(grid), *cpu);
        const RenderImage a = r1.render(std::nullopt, false).image, b = r2.render(std::nullopt, false).image;
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        double peak = 0.0, worst = 0.0;
        for (size_t i = 0; i < a.pixels.size(); ++i) {
            peak = std::max(peak, double(a.pixels[i].rgba.w));
            worst = std::max(worst, double(glm::length(a.pixels[i].rgba - b.pixels[i].rgba)));
        }
        EXPECT_GT(peak, 0.5) << "the box is in view";
        EXPECT_LT(worst, 1e-5) << "shadows " << int(shadows);
    }
}

TEST(Transfer2d, EditingTheRegionsRereadsNoFile) {
    const std::string vdb = writeBall(tempDir("transfer_2d_edit"));
    Scene s;
    s.volume().path = vdb;
    s.render.width = s.render.height = 24;
    s.lights = {Light{}};
    TransferRegion region;
    region.value = {0.1f, 10.0f};
    region.extinction = 5.0f;
    s.volume().material.transfer_2d = {region};
    Renderer r(s);
    const auto ran = [](const FrameResult& f, const std::string& stage) {
        return std::any_of(f.stage_seconds.begin(), f.stage_seconds.end(), [&](const auto& p) { return p.first == stage; });
    };
    FrameResult f = r.render(std::nullopt, false);
    EXPECT_TRUE(ran(f, "load") && ran(f, "transfer_2d"));
    s.volume().material.transfer_2d[0].albedo = glm::vec3(0.5f);
    r.setScene(s);
    f = r.render(std::nullopt, false);
    EXPECT_FALSE(ran(f, "load"));
    EXPECT_TRUE(ran(f, "transfer_2d") && ran(f, "brick"));
    s.volume().material.transfer_2d.clear();   // back to the grid as density: the stage no longer runs
    r.setScene(s);
    f = r.render(std::nullopt, false);
    EXPECT_FALSE(ran(f, "load") || ran(f, "transfer_2d"));
    EXPECT_TRUE(ran(f, "brick"));
}

// A CT phantom in HU, 1 mm voxels: a bone ball (1000) inside soft tissue (40) out to r = 10 mm,
// then a 2 mm ramp to air (-1000), as a scanner's partial volumes blur the skin. The ct_tissue
// preset classifies the bone as bone, the tissue as soft tissue, the ramp's middle as skin (Kniss's
// boundary triangle: a gradient of 520 HU/mm at values between air and tissue), and air as nothing.
TEST(Transfer2d, CtPresetTellsBoneTissueSkinAndAirApart) {
    initOpenVdb();
    const auto hu = [](double r) { return r <= 4.0 ? 1000.0 : r <= 10.0 ? 40.0 : std::max(-1000.0, 40.0 - 520.0 * (r - 10.0)); };
    auto grid = openvdb::FloatGrid::create(-1000.0f);
    auto acc = grid->getAccessor();
    for (int z = -16; z <= 16; ++z)
        for (int y = -16; y <= 16; ++y)
            for (int x = -16; x <= 16; ++x) {
                const float v = float(hu(std::sqrt(double(x * x + y * y + z * z))));
                if (v > -1000.0f) acc.setValueOn({x, y, z}, v);
            }
    const TransferPreset* ct = findTransferPreset("ct_tissue");
    ASSERT_NE(ct, nullptr);
    const auto albedoOf = [&](const char* name) {
        for (const TransferRegion& r : ct->regions)
            if (r.name == name) return openvdb::Vec3s(r.albedo.x, r.albedo.y, r.albedo.z);
        ADD_FAILURE() << "no region " << name;
        return openvdb::Vec3s(0.0f);
    };
    std::vector<std::string> warnings;
    const LoadedVolume out = applyTransfer2d(volumeFromGrid(grid), ct->regions, warnings);
    auto sigma = out.density->getConstAccessor();
    auto colour = out.color->getConstAccessor();
    std::map<std::string, int> seen;
    for (int z = -16; z <= 16; ++z)
        for (int y = -16; y <= 16; ++y)
            for (int x = -16; x <= 16; ++x) {
                const double r = std::sqrt(double(x * x + y * y + z * z));
                const openvdb::Coord c(x, y, z);
                const char* region = r < 3.0 ? "bone" : r > 5.0 && r < 9.0 ? "soft tissue" : r > 10.6 && r < 11.3 ? "skin" : nullptr;
                if (region) {
                    ASSERT_TRUE(sigma.isValueOn(c)) << region << " at r " << r;
                    ASSERT_LT((colour.getValue(c) - albedoOf(region)).length(), 1e-6f) << region << " at r " << r;
                    ++seen[region];
                } else if (r > 12.5) {
                    ASSERT_FALSE(sigma.isValueOn(c)) << "air at r " << r;
                    ++seen["air"];
                }
            }
    for (const char* region : {"bone", "soft tissue", "skin", "air"}) EXPECT_GT(seen[region], 50) << region;
}

TEST(Transfer2d, PresetsAreNamedInTheScene) {
    const Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": "ct_bone"}})", "shot.json", "");
    ASSERT_EQ(s.volume().material.transfer_2d.size(), 1u);
    EXPECT_EQ(s.volume().material.transfer_2d[0].name, "bone");
    EXPECT_EQ(s.volume().material.transfer_2d[0].value, glm::vec2(300.0f, 3000.0f));
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": "ct_lungs"}})"),
              "shot.json: /material/transfer_function_2d: 'ct_lungs' is not a preset (ct_tissue, ct_bone, mri_t1_head) or a list of "
              "regions");
}

// What `voxlux scene` and the viewer's "Save scene" write reads back as the same regions, for
// every preset (open gradient ranges, fades, triangles) and the bundled head's own.
TEST(Transfer2d, RegionsSurviveWritingAndReadingTheScene) {
    std::vector<std::vector<TransferRegion>> lists;
    for (const TransferPreset& p : transferPresets()) lists.push_back(p.regions);
    lists.push_back(loadSceneFile(sourceDir() + "/grids/mri_head.json").volume().material.transfer_2d);
    for (const auto& regions : lists) {
        Scene s;
        s.volume().path = "a.vdb";
        s.volume().material.transfer_2d = regions;
        const Scene back = sceneFromJson(sceneToJson(s), "shot.json", "");
        ASSERT_EQ(back.volume().material.transfer_2d.size(), regions.size());
        for (size_t i = 0; i < regions.size(); ++i) {
            const TransferRegion &a = regions[i], &b = back.volume().material.transfer_2d[i];
            EXPECT_EQ(a.name, b.name);
            EXPECT_EQ(a.triangle, b.triangle);
            EXPECT_EQ(a.value, b.value) << a.name;
            EXPECT_EQ(a.gradient, b.gradient) << a.name;
            EXPECT_EQ(a.corners, b.corners) << a.name;
            EXPECT_EQ(a.fade, b.fade) << a.name;
            EXPECT_EQ(a.extinction, b.extinction) << a.name;
            EXPECT_EQ(a.albedo, b.albedo) << a.name;
            EXPECT_EQ(a.transport, b.transport) << a.name;
            EXPECT_EQ(a.surface, b.surface) << a.name;
        }
    }
}

TEST(Transfer2d, SceneErrorsNameTheRegion) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": [
                  {"value": [0, 1], "gradient": [0, 1], "extinction": 1}, {"triangle": [[0, 0], [1, 1], [2, 2]], "extinction": 1}]}})"),
              "shot.json: /material/transfer_function_2d/1/triangle: its corners lie on one line");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": [{"value": [5, 1], "extinction": 1}]}})"),
              "shot.json: /material/transfer_function_2d/0/value: expected [lo, hi], finite, with lo < hi");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function": [{"value": 0, "extinction": 0},
                  {"value": 1, "extinction": 1}], "transfer_function_2d": [{"value": [0, 1], "extinction": 1}]}})"),
              "shot.json: /material/transfer_function_2d: a material has one transfer function: remove transfer_function");
}

TEST(Transfer2d, TransportColoursComeOnEveryRegionOrNone) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": [
                  {"value": [0, 1], "extinction": 1, "transport": [1, 0.5, 0.5]}, {"name": "bone", "value": [1, 2], "extinction": 1}]}})"),
              "shot.json: /material/transfer_function_2d: give every region a transport colour or none: 'bone' has none");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": [
                  {"value": [0, 1], "extinction": 1}, {"value": [1, 2], "extinction": 1, "transport": [1, 0.5, 0.5]}]}})"),
              "shot.json: /material/transfer_function_2d: give every region a transport colour or none: the region at index 0 has none");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": [
                  {"value": [0, 1], "extinction": 1, "transport": [1, 0, 0.5]}]}})"),
              "shot.json: /material/transfer_function_2d/0/transport: each component must lie in (0, 1]");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": [
                  {"name": "skin", "value": [0, 1], "extinction": 1}, {"value": [1, 2], "extinction": 1, "surface": 1}]}})"),
              "shot.json: /material/transfer_function_2d: give every region a surface weight or none: 'skin' has none");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"transfer_function_2d": [
                  {"value": [0, 1], "extinction": 1, "surface": 1.5}]}})"),
              "shot.json: /material/transfer_function_2d/0/surface: must lie in [0, 1]");
}

TEST(Transfer2d, SurfaceWeightIsTheExtinctionWeightedMean) {
    TransferRegion skin, brain;
    skin.value = brain.value = {0.0f, 10.0f};
    skin.extinction = 1.0f;
    skin.surface = 1.0f;
    brain.extinction = 3.0f;
    brain.surface = 0.2f;
    EXPECT_NEAR(classify2d({skin, brain}, 5.0f, 0.0f).surface, (1.0f + 3.0f * 0.2f) / 4.0f, 1e-6f);
    EXPECT_EQ(classify2d({skin, brain}, 50.0f, 0.0f).surface, 1.0f);   // nothing selected
}

// Kniss's Eq. 8 per material: where regions overlap, their -ln(transport) mix as the albedo does,
// weighted by extinction, so that each channel's optical depth is the regions' summed.
TEST(Transfer2d, TransportIsTheExtinctionWeightedMeanOfMinusLogTransport) {
    TransferRegion half, quarter;
    half.value = quarter.value = {0.0f, 10.0f};
    half.extinction = 1.0f;
    half.transport = glm::vec3(0.5f, 1.0f, 0.25f);
    quarter.extinction = 3.0f;
    quarter.transport = glm::vec3(0.25f, 1.0f, 0.5f);
    const Classified k = classify2d({half, quarter}, 5.0f, 0.0f);
    EXPECT_FLOAT_EQ(k.extinction, 4.0f);
    // In powers of 2: -log2 T is (1, 0, 2) and (2, 0, 1), weighted 1 and 3: (7, 0, 5) / 4.
    EXPECT_NEAR(k.transport.x, std::exp2(-1.75f), 1e-6f);
    EXPECT_EQ(k.transport.y, 1.0f);
    EXPECT_NEAR(k.transport.z, std::exp2(-1.25f), 1e-6f);
    half.transport = quarter.transport = std::nullopt;
    EXPECT_EQ(classify2d({half, quarter}, 5.0f, 0.0f).transport, glm::vec3(1.0f));

    // The grid: a transport colour on exactly the selected voxels, and none without the key.
    auto grid = boxGrid({0, 0, 0}, {7, 7, 7}, 5.0f);
    half.transport = quarter.transport = glm::vec3(0.5f);
    std::vector<std::string> warnings;
    const LoadedVolume with = applyTransfer2d(volumeFromGrid(grid), {half, quarter}, warnings);
    ASSERT_TRUE(with.transport);
    EXPECT_EQ(with.transport->activeVoxelCount(), with.density->activeVoxelCount());
    EXPECT_NEAR(with.transport->tree().getValue(openvdb::Coord(3, 4, 5)).x(), 0.5f, 1e-6f);
    half.transport = quarter.transport = std::nullopt;
    EXPECT_FALSE(applyTransfer2d(volumeFromGrid(grid), {half, quarter}, warnings).transport);
}

}  // namespace
}  // namespace voxlux::test
