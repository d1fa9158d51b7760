// volume.transform: a cache placed in the scene on top of its file's own transform. The ray along
// a box's long axis, after a scale and a rotation, sees e^(-sigma L) with L the placed length;
// the same placement written into the file's own transform renders the same image; velocities and
// the up axis turn with the cache; the key is validated and written back.
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/component_wise.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/tools/GridTransformer.h>

#include <fstream>

#include "core/error.h"
#include "render/renderer.h"
#include "volume/vdb_loader.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

constexpr float kSigma = 0.1f;     // extinction per world unit inside the box
constexpr double kVoxel = 0.5;     // the file's own transform: half-unit voxels
// 16 x 4 x 4 voxels: 8 x 2 x 2 world units in the file, the long axis along x.
openvdb::FloatGrid::Ptr longBox() { return boxGrid({-8, -2, -2}, {7, 1, 1}, kSigma, kVoxel); }
// 17 x 5 x 5 voxels centred on the origin: 8.5 x 2.5 x 2.5 world units under trilinear ramps.
openvdb::FloatGrid::Ptr centredBox() { return boxGrid({-8, -2, -2}, {8, 2, 2}, kSigma, kVoxel); }

// The box's centre after `placement`, and a scene looking at it along -`axis` from far away.
Scene lookingAlong(const std::string& file, const glm::mat4& placement, glm::vec3 axis) {
    Scene s;
    s.volume().path = file;
    s.render.width = s.render.height = 33;   // odd: the centre pixel's ray is the camera's axis
    s.render.backend = Backend::Cpu;
    const glm::vec3 centre(placement * glm::vec4(-0.25f, -0.25f, -0.25f, 1.0f));   // the voxel box's centre, in file world units
    Camera c;
    c.position = centre + 60.0f * axis;
    c.look_at = centre;
    c.up = std::abs(axis.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
    c.fov = 20.0f;
    s.camera = c;
    return s;
}

float centreTransmittance(const RenderImage& image) { return 1.0f - image.pixels[size_t(16 * 33 + 16)].rgba.w; }

// `placement` written into a grid of half-unit voxels as its own transform: OpenVDB's row-vector
// matrix is glm's column-major one read row by row.
void placeInFile(openvdb::GridBase& grid, const glm::mat4& placement) {
    const glm::mat4 index_to_world = placement * glm::mat4(glm::vec4(kVoxel, 0, 0, 0), glm::vec4(0, kVoxel, 0, 0),
                                                           glm::vec4(0, 0, kVoxel, 0), glm::vec4(0, 0, 0, 1));
    openvdb::math::Mat4d mat;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) mat[i][j] = index_to_world[i][j];
    grid.setTransform(openvdb::math::Transform::createLinearTransform(mat));
}

// An oblique pose: every axis turned, scaled differently and moved.
VolumeTransform obliquePose() {
    VolumeTransform t;
    t.translate = glm::vec3(0.5f, 0.25f, -1.0f);
    t.rotate = glm::vec3(20.0f, -35.0f, 60.0f);
    t.scale = glm::vec3(1.5f, 0.75f, 1.2f);
    return t;
}

// The largest difference of any channel of any pixel between two images of one size.
float largestDifference(const RenderImage& a, const RenderImage& b) {
    float largest = 0.0f;
    for (size_t i = 0; i < a.pixels.size(); ++i) largest = std::max(largest, glm::compMax(glm::abs(a.pixels[i].rgba - b.pixels[i].rgba)));
    return largest;
}

// `in_scene`, placed by its volume's transform, and the same scene reading `placed_file` (the
// placement written into the file) without one.
std::pair<RenderImage, RenderImage> placedAndInFile(const Scene& in_scene, const std::string& placed_file) {
    Scene in_file = in_scene;
    in_file.volume().path = placed_file;
    in_file.volume().transform.reset();
    return {Renderer(in_scene).render(std::nullopt, false).image, Renderer(in_file).render(std::nullopt, false).image};
}

TEST(VolumeTransform, TheLongAxisAfterScaleAndRotationHoldsThePlacedOpticalDepth) {
    const std::string dir = tempDir("volume-transform");
    const std::string file = dir + "/long_box.vdb";
    openvdb::io::File(file).write({longBox()});
    // Scale x by 2 (8 -> 16 units), then turn 90 degrees about X (x stays), then 90 about Z
    // (x -> y): the long axis ends along y. The other order (Z first) would put it along z.
    VolumeTransform t;
    t.translate = glm::vec3(3.0f, -1.0f, 2.0f);
    t.rotate = glm::vec3(90.0f, 0.0f, 90.0f);
    t.scale = glm::vec3(2.0f, 1.0f, 1.0f);
    const glm::mat4 m = volumeTransformMatrix(t);
    EXPECT_NEAR(glm::length(glm::vec3(m * glm::vec4(1, 0, 0, 0)) - glm::vec3(0, 2, 0)), 0.0f, 1e-6f);
    Scene along_y = lookingAlong(file, m, glm::vec3(0, 1, 0));
    along_y.volume().transform = t;
    const float expected = std::exp(-kSigma * 16.0f);   // trilinear ramps keep the box's integral
    EXPECT_NEAR(centreTransmittance(Renderer(along_y).render(std::nullopt, false).image), expected, 2e-3f);
    // Across the long axis (along z after the turn, 2 units wide): e^(-sigma 2).
    Scene along_z = lookingAlong(file, m, glm::vec3(0, 0, 1));
    along_z.volume().transform = t;
    EXPECT_NEAR(centreTransmittance(Renderer(along_z).render(std::nullopt, false).image), std::exp(-kSigma * 2.0f), 2e-3f);
    // Untransformed, the y ray crosses the box's 2-unit width.
    const Scene plain = lookingAlong(file, glm::mat4(1.0f), glm::vec3(0, 1, 0));
    EXPECT_NEAR(centreTransmittance(Renderer(plain).render(std::nullopt, false).image), std::exp(-kSigma * 2.0f), 2e-3f);
}

TEST(VolumeTransform, RendersAsThePlacementWrittenIntoTheFile) {
    const std::string dir = tempDir("volume-transform-file");
    const VolumeTransform t = obliquePose();
    const glm::mat4 m = volumeTransformMatrix(t);
    const std::string file = dir + "/box.vdb";
    openvdb::io::File(file).write({longBox()});
    auto placed = longBox();   // the same placement, as the file's own transform
    placeInFile(*placed, m);
    const std::string placed_file = dir + "/placed.vdb";
    openvdb::io::File(placed_file).write({placed});

    Scene in_scene = lookingAlong(file, m, glm::normalize(glm::vec3(0.3f, 0.4f, 1.0f)));
    in_scene.volume().transform = t;
    const auto [a, b] = placedAndInFile(in_scene, placed_file);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    float covered = 0.0f;
    for (const auto& px : a.pixels) covered = std::max(covered, px.rgba.w);
    EXPECT_GT(covered, 0.3f);   // the box is in view
    EXPECT_LE(largestDifference(a, b), 1e-5f);
}

// A smooth ellipsoid of semi-axes 12 x 6 x 4 voxels, half-unit voxels: what a resampler carries
// into another pose without losing its shape to aliasing.
openvdb::FloatGrid::Ptr ellipsoid() {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setTransform(openvdb::math::Transform::createLinearTransform(kVoxel));
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto acc = grid->getAccessor();
    for (int z = -5; z <= 5; ++z)
        for (int y = -7; y <= 7; ++y)
            for (int x = -13; x <= 13; ++x) {
                const float r2 = float(x * x) / 144.0f + float(y * y) / 36.0f + float(z * z) / 16.0f;
                if (r2 < 1.0f) acc.setValue(openvdb::Coord(x, y, z), 0.6f * (1.0f - r2) * (1.0f - r2));
            }
    return grid;
}

// The issue's check against an independent resampler: the placed cache renders as OpenVDB's
// tools::resampleToMatch of it into the placed pose, on an axis-aligned grid of quarter-unit
// voxels, rendered without a transform. Their difference is the resampler's trilinear blur.
TEST(VolumeTransform, RendersAsOpenVdbsResamplingIntoThePose) {
    const std::string dir = tempDir("volume-transform-resampled");
    const VolumeTransform t = obliquePose();
    const glm::mat4 m = volumeTransformMatrix(t);
    const std::string file = dir + "/ellipsoid.vdb";
    openvdb::io::File(file).write({ellipsoid()});

    auto posed = ellipsoid();   // the same voxels under the placed index-to-world
    placeInFile(*posed, m);
    auto resampled = openvdb::FloatGrid::create(0.0f);
    resampled->setName("density");
    resampled->setGridClass(openvdb::GRID_FOG_VOLUME);
    resampled->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*posed, *resampled);
    const std::string resampled_file = dir + "/resampled.vdb";
    openvdb::io::File(resampled_file).write({resampled});

    Scene placed = lookingAlong(file, glm::translate(m, glm::vec3(0.25f)), glm::normalize(glm::vec3(0.2f, -0.5f, 1.0f)));
    placed.volume().transform = t;
    placed.render.step = 0.25f;
    const auto [a, b] = placedAndInFile(placed, resampled_file);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    float covered = 0.0f, largest = 0.0f;
    double total = 0.0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        covered = std::max(covered, a.pixels[i].rgba.w);
        const float d = glm::compMax(glm::abs(a.pixels[i].rgba - b.pixels[i].rgba));
        largest = std::max(largest, d);
        total += d;
    }
    std::printf("  placed against resampled: largest difference %.4f, mean %.5f, peak alpha %.3f\n", largest, total / double(a.pixels.size()), covered);
    EXPECT_GT(covered, 0.3f);
    // Measured: 0.016 and 0.0003. A rotation about the wrong axes or in the wrong order moves the
    // ellipsoid by whole pixels, differences of the order of its alpha.
    EXPECT_LE(largest, 0.025f);
    EXPECT_LE(total / double(a.pixels.size()), 0.001);
}

// The medium moves as it is placed: a moving box under motion blur, placed by the scene, renders
// as the placement and the turned velocities written into the file (the kernel turns the file's
// velocities by the placement). The default view's up turns with it.
TEST(VolumeTransform, TurnsAndScalesTheVelocitiesAndTheUpAxis) {
    const std::string dir = tempDir("volume-transform-velocity");
    VolumeTransform t;
    t.rotate = glm::vec3(90.0f, 0.0f, 90.0f);   // x -> y, and y -> z
    t.scale = glm::vec3(2.0f);
    const glm::mat4 m = volumeTransformMatrix(t);
    const auto moving = [&](const glm::mat4& placement, glm::vec3 velocity) {
        auto box = longBox();
        auto vel = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
        vel->setName("vel");
        placeInFile(*box, placement);
        vel->setTransform(box->transform().copy());
        vel->denseFill(openvdb::CoordBBox({-8, -2, -2}, {7, 1, 1}), openvdb::Vec3s(velocity.x, velocity.y, velocity.z), true);
        return std::vector<openvdb::GridBase::Ptr>{box, vel};
    };
    const std::string file = dir + "/moving.vdb", placed_file = dir + "/placed.vdb";
    openvdb::io::File(file).write(moving(glm::mat4(1.0f), glm::vec3(80.0f, 0.0f, 0.0f)));
    openvdb::io::File(placed_file).write(moving(m, glm::vec3(0.0f, 160.0f, 0.0f)));   // (80, 0, 0) turned and doubled
    // (Moving 1.67 voxels within the shutter: a reach of a whole number of voxels would round up
    // by a voxel on one side from the placed transform's rounding.)

    Scene in_scene = lookingAlong(file, m, glm::vec3(0, 0, 1));   // across the motion, which is along y after the turn
    in_scene.volume().transform = t;
    in_scene.render.motion_blur = MotionBlur{};
    const auto [a, b] = placedAndInFile(in_scene, placed_file);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    Scene still = in_scene;   // the blur is there to be turned
    still.render.motion_blur.reset();
    const RenderImage c = Renderer(still).render(std::nullopt, false).image;
    float blur = 0.0f;
    for (size_t i = 0; i < a.pixels.size(); ++i) blur = std::max(blur, std::abs(a.pixels[i].rgba.w - c.pixels[i].rgba.w));
    EXPECT_LE(largestDifference(a, b), 1e-4f);
    EXPECT_GT(blur, 0.05f);

    const LoadedVolume v = placedVolume(loadVolume(file, VolumeSpec{}), m);
    // The file says nothing of its up axis: Y, which the turn takes to Z.
    EXPECT_NEAR(glm::length(v.up.frame[1] - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::determinant(v.up.frame), 1.0f, 1e-6f);
    EXPECT_EQ(v.up.axis, 2);
    EXPECT_EQ(v.up.reason, "y (the file does not say; OpenVDB's convention), turned by volume.transform");
}

// A move is applied after the bricks: editing the transform re-reads and re-bricks nothing.
TEST(VolumeTransform, AMoveReloadsAndRebricksNothing) {
    const std::string dir = tempDir("volume-transform-move");
    const std::string file = dir + "/box.vdb";
    openvdb::io::File(file).write({centredBox()});
    Scene s = lookingAlong(file, glm::translate(glm::mat4(1.0f), glm::vec3(0.25f)), glm::vec3(1, 0, 0));
    s.effects.shadows = ShadowMethod::SatCone;
    Renderer renderer(s);
    EXPECT_NEAR(centreTransmittance(renderer.render(std::nullopt, false).image), std::exp(-kSigma * 8.5f), 2e-3f);
    s.volume().transform = VolumeTransform{};
    s.volume().transform->rotate = glm::vec3(0.0f, 0.0f, 90.0f);
    renderer.setScene(s);
    const FrameResult moved = renderer.render(std::nullopt, false);
    EXPECT_NEAR(centreTransmittance(moved.image), std::exp(-kSigma * 2.5f), 2e-3f);
    for (const char* stage : {"load", "brick", "classify"})
        EXPECT_NE(std::find(moved.reused.begin(), moved.reused.end(), stage), moved.reused.end()) << stage;
    for (const char* stage : {"light_grid", "sat", "light_cache", "march"})
        EXPECT_EQ(std::find(moved.reused.begin(), moved.reused.end(), stage), moved.reused.end()) << stage;
}

TEST(VolumeTransform, IsValidatedAndWrittenBack) {
    const std::string v = R"({"volume": {"path": "a.vdb", "transform": )";
    EXPECT_EQ(sceneErrorOf(v + R"({"scale": 0}}})"),
              "shot.json: /volume/transform/scale: must be finite and > 0 (a number, or one per axis)");
    EXPECT_EQ(sceneErrorOf(v + R"({"scale": [1, -1, 1]}}})"),
              "shot.json: /volume/transform/scale: must be finite and > 0 (a number, or one per axis)");
    EXPECT_EQ(sceneErrorOf(v + R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "rotate": [0, 90, 0]}}})"),
              "shot.json: /volume/transform/rotate: goes with translate, rotate and scale, not with a matrix");
    EXPECT_EQ(sceneErrorOf(v + R"({"matrix": [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,1]}}})"),
              "shot.json: /volume/transform/matrix: its rotation part (elements 0-10) must be invertible");
    EXPECT_EQ(sceneErrorOf(v + R"({"spin": 3}}})"),
              "shot.json: /volume/transform/spin: unknown key (expected one of translate, rotate, scale, rotate_order, matrix, keys, chan)");

    const Scene s = parseScene(R"({"volume": {"path": "a.vdb", "transform": {"rotate": [0, 90, 0], "scale": 2}}})", "shot.json", "");
    ASSERT_TRUE(s.volume().transform);
    EXPECT_EQ(s.volume().transform->scale, glm::vec3(2.0f));
    EXPECT_EQ(sceneToJson(s)["volumes"][0]["transform"],
              nlohmann::json::parse(R"({"translate": [0, 0, 0], "rotate": [0, 90, 0], "scale": [2, 2, 2]})"));
    EXPECT_EQ(sceneToJson(parseScene(sceneToJson(s).dump(), "again.json", "")), sceneToJson(s));
    // A scene without one writes none, and hashes as before.
    EXPECT_FALSE(sceneToJson(parseScene(R"({"volume": {"path": "a.vdb"}})", "shot.json", ""))["volumes"][0].contains("transform"));
}

glm::vec3 turnedX(const VolumeTransform& t, std::optional<double> frame = std::nullopt) {
    return glm::vec3(volumeTransformMatrix(t, frame) * glm::vec4(1, 0, 0, 0));
}

TEST(VolumeTransform, RotateOrderTurnsInTheOrderNamed) {
    VolumeTransform t;
    t.rotate = glm::vec3(90.0f, 0.0f, 90.0f);
    // X first (x stays), then Z: x -> y.
    EXPECT_NEAR(glm::length(turnedX(t) - glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    // Nuke's ZXY: Z first (x -> y), then X (y -> z).
    t.rotate_order = RotateOrder::Zxy;
    EXPECT_NEAR(glm::length(turnedX(t) - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

VolumeTransform keyedTurn() {
    VolumeTransform t;
    t.keys = {{1.0, glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(1.0f)},
              {3.0, glm::vec3(2.0f, 4.0f, 6.0f), glm::vec3(0.0f, 0.0f, 90.0f), glm::vec3(1.0f, 1.0f, 3.0f)}};
    return t;
}

TEST(VolumeTransform, KeysBlendLinearlyAndHoldBeyondTheirEnds) {
    const VolumeTransform t = keyedTurn();
    VolumeTransform middle;
    middle.translate = glm::vec3(1.0f, 2.0f, 3.0f);
    middle.rotate = glm::vec3(0.0f, 0.0f, 45.0f);
    middle.scale = glm::vec3(1.0f, 1.0f, 2.0f);
    const glm::mat4 a = volumeTransformMatrix(t, 2.0), b = volumeTransformMatrix(middle);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(glm::length(a[c] - b[c]), 0.0f, 1e-6f) << "column " << c;
    EXPECT_EQ(volumeTransformMatrix(t, -5.0), glm::mat4(1.0f));
    EXPECT_EQ(volumeTransformMatrix(t, std::nullopt), glm::mat4(1.0f));   // a still: the first key
    EXPECT_NEAR(glm::length(glm::vec3(volumeTransformMatrix(t, 40.0)[3]) - glm::vec3(2, 4, 6)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(turnedX(t, 40.0) - glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
}


// A sequence of three frames of the centred box, seen along -x from far away.
Scene keyedSequence(const std::string& dir) {
    for (int frame = 1; frame <= 3; ++frame) openvdb::io::File(dir + "/box_000" + std::to_string(frame) + ".vdb").write({centredBox()});
    Scene s = lookingAlong(dir + "/box_####.vdb", glm::translate(glm::mat4(1.0f), glm::vec3(0.25f)), glm::vec3(1, 0, 0));
    s.volume().frames = FrameSet(1, 3);
    return s;
}

// Frame 1 looks down the long axis (8.5 units), frame 3 across it after a quarter turn about Z
// (2.5), and frame 2, halfway through the turn, crosses the 2.5-unit width at 45 degrees.
TEST(VolumeTransform, AKeyedSequenceRendersEachFrameInItsPose) {
    Scene s = keyedSequence(tempDir("volume-transform-keyed"));
    s.volume().transform = keyedTurn();
    for (TransformKey& k : s.volume().transform->keys) k.translate = glm::vec3(0.0f), k.scale = glm::vec3(1.0f);
    Renderer renderer(s);
    EXPECT_NEAR(centreTransmittance(renderer.render(1, false).image), std::exp(-kSigma * 8.5f), 2e-3f);
    EXPECT_NEAR(centreTransmittance(renderer.render(2, false).image), std::exp(-kSigma * 2.5f * std::sqrt(2.0f)), 2e-3f);
    EXPECT_NEAR(centreTransmittance(renderer.render(3, false).image), std::exp(-kSigma * 2.5f), 2e-3f);
}

// The same turn from a Nuke .chan file: read with the scene, written back as the file's name, and
// an edit of the file re-places the volume.
TEST(VolumeTransform, AChanFileKeysTheTransformAndItsEditsRerenderIt) {
    const std::string dir = tempDir("volume-transform-chan");
    std::ofstream(dir + "/turn.chan") << "1 0 0 0 0 0 0\n3 0 0 0 0 0 90\n";
    Scene s = keyedSequence(dir);
    nlohmann::json j = sceneToJson(s);
    j["volumes"][0]["transform"] = {{"chan", "turn.chan"}, {"rotate_order", "zxy"}};
    s = parseScene(j.dump(), dir + "/shot.json", dir);
    ASSERT_TRUE(s.volume().transform);
    ASSERT_EQ(s.volume().transform->keys.size(), 2u);
    EXPECT_EQ(s.volume().transform->rotate_order, RotateOrder::Zxy);
    EXPECT_EQ(sceneToJson(s)["volumes"][0]["transform"],
              nlohmann::json({{"chan", dir + "/turn.chan"}, {"rotate_order", "zxy"}, {"scale", {1, 1, 1}}}));
    EXPECT_EQ(sceneToJson(parseScene(sceneToJson(s).dump(), "again.json", "")), sceneToJson(s));

    Renderer renderer(s);
    EXPECT_NEAR(centreTransmittance(renderer.render(2, false).image), std::exp(-kSigma * 2.5f * std::sqrt(2.0f)), 2e-3f);
    std::ofstream(dir + "/turn.chan") << "1 0 0 0 0 0 0\n3 0 0 0 0 0 180.0\n";   // longer: a new identity even within the same second
    renderer.setScene(parseScene(j.dump(), dir + "/shot.json", dir));
    EXPECT_NEAR(centreTransmittance(renderer.render(2, false).image), std::exp(-kSigma * 2.5f), 2e-3f);
}

TEST(VolumeTransform, KeysAreValidated) {
    const std::string v = R"({"volume": {"path": "a_####.vdb", "frames": [1, 3], "transform": )";
    EXPECT_EQ(sceneErrorOf(v + R"([{"frame": 1}, {"frame": 1, "rotate": [0, 0, 90]}]}})"),
              "shot.json: /volume/transform/1/frame: must follow the previous key's frame");
    EXPECT_EQ(sceneErrorOf(v + R"([{"translate": [0, 0, 0]}]}})"), "shot.json: /volume/transform/0/frame: is required in every key");
    EXPECT_EQ(sceneErrorOf(v + R"({"keys": [{"frame": 1}], "scale": 2}}})"),
              "shot.json: /volume/transform/scale: goes in each key of keys, not beside them");
    EXPECT_EQ(sceneErrorOf(v + R"({"keys": []}}})"),
              "shot.json: /volume/transform/keys: expected a list of {\"frame\": f, \"translate\": ..., \"rotate\": ..., \"scale\": ...}");
    EXPECT_EQ(sceneErrorOf(v + R"({"chan": "a.chan", "translate": [1, 0, 0]}}})"),
              "shot.json: /volume/transform/translate: comes from the .chan file, which gives translate and rotate per frame");
    EXPECT_EQ(sceneErrorOf(v + R"({"chan": "missing.chan"}}})"), "/shots/missing.chan: cannot open .chan file");
    EXPECT_EQ(sceneErrorOf(v + R"({"rotate_order": "xxy"}}})"),
              "shot.json: /volume/transform/rotate_order: 'xxy' is not one of xyz, xzy, yxz, yzx, zxy, zyx");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb", "transform": [{"frame": 1}]}})"),
              "shot.json: /volume/transform: is keyed per frame, but path names one file, not a #### sequence");
    const Scene s = parseScene(v + R"([{"frame": 1, "scale": 2}, {"frame": 2.5, "translate": [1, 0, 0]}]}})", "shot.json", "");
    EXPECT_EQ(sceneToJson(s)["volumes"][0]["transform"],
              nlohmann::json::parse(R"({"keys": [{"frame": 1.0, "translate": [0, 0, 0], "rotate": [0, 0, 0], "scale": [2, 2, 2]},
                                                 {"frame": 2.5, "translate": [1, 0, 0], "rotate": [0, 0, 0], "scale": [1, 1, 1]}]})"));
    EXPECT_EQ(sceneToJson(parseScene(sceneToJson(s).dump(), "again.json", "")), sceneToJson(s));
}

}  // namespace
}  // namespace voxlux::test
