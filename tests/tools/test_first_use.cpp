// What a new user meets first: the quick form's choices (up axis, density, blackbody brightness),
// one camera per sequence, exposure, `voxlux scene`, `--explain`, output extensions, `info`,
// progress and Ctrl-C.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <ImfFloatAttribute.h>
#include <ImfStandardAttributes.h>
#include <nlohmann/json.hpp>

#include "optics/blackbody.h"
#include "test_support.h"
#include "tools/quick_form.h"
#include "volume/up_axis.h"

namespace voxlux::test {
namespace {
namespace fs = std::filesystem;

std::string writeGrids(const std::string& path, const openvdb::GridPtrVec& grids) {
    openvdb::io::File(path).write(grids);
    return path;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(FirstUse, UpAxisIsReadFromWhatEachWriterLeaves) {
    openvdb::MetaMap file, grid;
    EXPECT_EQ(detectUpAxis(file, grid).axis, 1);
    EXPECT_EQ(detectUpAxis(file, grid).reason, "y (the file does not say; OpenVDB's convention)");
    grid.insertMeta("file_base_resolution", openvdb::Vec3IMetadata(openvdb::Vec3i(43, 43, 64)));
    EXPECT_EQ(detectUpAxis(file, grid).axis, 2);
    EXPECT_EQ(detectUpAxis(file, grid).reason, "z (a Blender Mantaflow cache: grids carry file_base_resolution)");
    openvdb::MetaMap local;
    local.insertMeta("is_local_space", openvdb::BoolMetadata(true));
    EXPECT_EQ(detectUpAxis(file, local).axis, 2);
    file.insertMeta("creator", openvdb::StringMetadata("Houdini/SOP_OpenVDB_Write"));
    EXPECT_EQ(detectUpAxis(file, local).axis, 1);   // Houdini names itself: its local space is Y-up
    EXPECT_EQ(detectUpAxis(file, local).reason, "y (creator 'Houdini/SOP_OpenVDB_Write')");
    openvdb::MetaMap blender;
    blender.insertMeta("creator", openvdb::StringMetadata("Blender/Smoke"));
    EXPECT_EQ(detectUpAxis(blender, openvdb::MetaMap()).axis, 2);
}

// A 10-voxel-deep box of 0.5 along the view: every column sums to 5, so the density scale that
// puts an optical depth of 2 in the median column is 0.4 per voxel, whatever the voxel size.
TEST(FirstUse, QuickFormDensityComesFromTheDataInVoxelUnits) {
    const std::string dir = tempDir("quick_density");
    for (double voxel : {0.01, 1.0, 30.0}) {
        const std::string file = writeGrids(dir + "/box" + std::to_string(int(voxel * 100)) + ".vdb",
                                            {boxGrid({0, 0, 0}, {19, 19, 9}, 0.5f, voxel)});
        std::vector<std::string> notes;
        const Scene s = completeQuickScene(quickScene(file), SceneOverrides{}, std::nullopt, notes);
        EXPECT_EQ(s.volume().material.density_units, DensityUnits::Voxel);
        EXPECT_NEAR(s.volume().material.density_scale, 0.4f, 1e-6f) << voxel;
        ASSERT_EQ(notes.size(), 2u);
        EXPECT_EQ(notes[1], "quick form: density_scale 0.4 per voxel: the median column along the view holds an optical "
                            "depth of 2 (--density-scale to change, in voxel units)");
    }
    // A value the user gave is kept.
    SceneOverrides given;
    given.density_scale = 3.0f;
    std::vector<std::string> notes;
    const Scene s = completeQuickScene(applyOverrides(quickScene(dir + "/box100.vdb"), given), given, std::nullopt, notes);
    EXPECT_EQ(s.volume().material.density_units, DensityUnits::World);
    EXPECT_EQ(s.volume().material.density_scale, 3.0f);
}

// In voxel units a look carries over between caches of any scale: the same voxels at voxel size
// 0.02 and 50 give the same image (the default camera frames each the same way).
TEST(FirstUse, DensityInVoxelUnitsGivesTheSameLookAtAnyScale) {
    const std::string dir = tempDir("voxel_units");
    std::vector<std::vector<float>> alphas;
    for (double voxel : {0.02, 50.0}) {
        const std::string tag = std::to_string(int(voxel * 100));
        const std::string file = writeGrids(dir + "/ball" + tag + ".vdb", {boxGrid({0, 0, 0}, {15, 11, 7}, 0.3f, voxel)});
        const std::string out = dir + "/out" + tag + ".exr";
        CliResult r = runCli("render " + file + " --res 32x32 --backend cpu --shadows none --density-scale 0.25 "
                             "--set material.density_units=voxel -o " + out);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        alphas.push_back(readExr(out).planes.at("A"));
    }
    float peak = 0.0f;
    for (size_t i = 0; i < alphas[0].size(); ++i) {
        EXPECT_NEAR(alphas[0][i], alphas[1][i], 2e-3f) << i;
        peak = std::max(peak, alphas[0][i]);
    }
    // 16 voxels of 0.3 x 0.25 through the thickest part: 1 - e^-1.2 = 0.70 at most, seen obliquely.
    EXPECT_GT(peak, 0.5f);
    EXPECT_LT(peak, 0.95f);
}

// Exposure scales light by 2^stops before the output transform, never alpha, and is recorded.
TEST(FirstUse, ExposureScalesLightByStopsAndIsRecorded) {
    const std::string dir = tempDir("exposure");
    const std::string base = "render " + sourceDir() +
                             "/grids/default.json --res 40x25 --backend cpu --pixel-type float --aovs direct";
    ASSERT_EQ(runCli(base + " -o " + dir + "/zero.exr").exit_code, 0);
    CliResult r = runCli(base + " --set render.exposure=1.5 -o " + dir + "/lifted.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Exr zero = readExr(dir + "/zero.exr"), lifted = readExr(dir + "/lifted.exr");
    const float gain = std::exp2(1.5f);
    for (const char* channel : {"R", "G", "B", "direct.R"})
        for (size_t i = 0; i < zero.planes.at(channel).size(); ++i)
            ASSERT_NEAR(lifted.planes.at(channel)[i], gain * zero.planes.at(channel)[i], 1e-5f + 1e-5f * lifted.planes.at(channel)[i]);
    EXPECT_EQ(lifted.planes.at("A"), zero.planes.at("A"));
    EXPECT_EQ(lifted.header.typedAttribute<Imf::FloatAttribute>("voxlux/exposure").value(), 1.5f);
    EXPECT_EQ(zero.header.typedAttribute<Imf::FloatAttribute>("voxlux/exposure").value(), 0.0f);
}

TEST(FirstUse, OutputExtensionsNeverLie) {
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    const std::string dir = tempDir("extensions");
    CliResult r = runCli("render " + cloud + " -o " + dir + "/out.png");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: -o: /output/path: '" + dir + "/out.png' does not end in .exr: the image is written as "
                     "OpenEXR (an sRGB PNG is the preview: output.preview, or --preview FILE.png)\n");
    r = runCli("render " + cloud + " -o " + dir + "/out.exr --preview " + dir + "/out.exr.jpg");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --preview: /output/preview: '" + dir + "/out.exr.jpg' does not end in .png: the preview "
                     "is written as PNG\n");
    EXPECT_TRUE(fs::is_empty(dir));
    r = runCli("render " + cloud + " --res 16x16 --backend cpu -o " + dir + "/OUT.EXR --preview " + dir + "/out.PNG");
    EXPECT_EQ(r.exit_code, 0) << r.err;
}

// `voxlux scene` writes a scene that renders as written, from any folder, for files and sequences.
TEST(FirstUse, SceneWritesARenderableScene) {
    const std::string dir = tempDir("scene_cmd");
    fs::create_directories(dir + "/shots/a");
    fs::create_directories(dir + "/caches");
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    for (int f : {1, 2}) fs::copy_file(cloud, dir + "/caches/cloud." + std::to_string(f) + ".vdb", fs::copy_options::overwrite_existing);
    CliResult r = runCli("scene " + dir + "/caches/cloud.#.vdb --frames 1-2 --res 16x16 -o " + dir + "/shots/a/shot.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, "wrote " + dir + "/shots/a/shot.json\n");
    EXPECT_NE(r.err.find("voxlux: camera framed on the frames on disk, 1-2, together (--frame-on N for one frame)"), std::string::npos)
        << r.err;
    // The cache was given by an absolute path, and the scene keeps it so.
    const auto j = nlohmann::json::parse(slurp(dir + "/shots/a/shot.json"));
    EXPECT_EQ(j["volumes"][0]["path"], dir + "/caches/cloud.#.vdb");
    EXPECT_EQ(j["output"]["path"], "cloud.#.exr");
    EXPECT_TRUE(j.contains("camera"));
    // Rendered from another folder: the volume is found beside the scene, the image lands here.
    const std::string render = "cd " + dir + " && " + voxluxBinary() + " render shots/a/shot.json --backend cpu >/dev/null";
    ASSERT_EQ(std::system(render.c_str()), 0);
    EXPECT_TRUE(fs::exists(dir + "/cloud.1.exr"));
    EXPECT_TRUE(fs::exists(dir + "/cloud.2.exr"));
    // Given relative to the folder the command runs in, it is written relative to the scene's folder.
    ASSERT_EQ(std::system(("cd " + dir + " && " + voxluxBinary() + " scene caches/cloud.#.vdb --frames 1-2 -o shots/a/rel.json 2>/dev/null >/dev/null").c_str()), 0);
    EXPECT_EQ(nlohmann::json::parse(slurp(dir + "/shots/a/rel.json"))["volumes"][0]["path"], "../../caches/cloud.#.vdb");
    // To standard output the volume path is absolute, and the image is named after the cache.
    r = runCli("scene " + cloud);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto printed = nlohmann::json::parse(r.out);
    EXPECT_EQ(printed["volumes"][0]["path"], fs::absolute(cloud).lexically_normal().string());
    EXPECT_EQ(printed["output"]["path"], "cloud.exr");
}

// --explain prints the graph, then what stops the render, without reading voxels.
TEST(FirstUse, ExplainSaysWhatIsMissing) {
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    CliResult r = runCli("render " + cloud + " --explain");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.out.find("\ncannot render:\n  no output path: pass -o FILE.exr or set output.path in the scene\n"),
              std::string::npos) << r.out;
    EXPECT_EQ(r.err, "voxlux: error: no output path: pass -o FILE.exr or set output.path in the scene\n");
    r = runCli("render " + cloud + " --explain --grid smoke --color-grid Cd -o x.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.out.find("cannot render:\n  " + cloud + ": no grid named 'smoke' (grids: 'density' (float); --grid density to render it)\n  " +
                         cloud + ": no grid named 'Cd' (grids: 'density' (float))\n"),
              std::string::npos) << r.out;
    r = runCli("render /nonexistent/cache.vdb --explain -o x.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: /nonexistent/cache.vdb: no such file\n");
    r = runCli("render " + cloud + " --explain -o x.exr");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.find("cannot render"), std::string::npos);
}

TEST(FirstUse, InfoReportsWhatATdChecksFirst) {
    const std::string dir = tempDir("info");
    auto a = boxGrid({0, 0, 0}, {9, 19, 4}, 0.25f, 0.5);
    auto b = boxGrid({-8, 0, 0}, {-1, 7, 7}, 2.0f, 2.0);
    b->tree().setValueOn(openvdb::Coord(-8, 0, 0), -1.0f);
    const std::string file = writeGrids(dir + "/two.vdb", {a, b});
    CliResult r = runCli("info " + file + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto grids = nlohmann::json::parse(r.out)["grids"];
    ASSERT_EQ(grids.size(), 2u);
    EXPECT_EQ(grids[0]["index"], 0);
    EXPECT_EQ(grids[1]["index"], 1);   // both are named density
    EXPECT_EQ(grids[0]["value_range"], nlohmann::json::parse("[0.25, 0.25]"));
    EXPECT_EQ(grids[1]["value_range"], nlohmann::json::parse("[-1.0, 2.0]"));
    EXPECT_EQ(grids[0]["world_min"], nlohmann::json::parse("[0.0, 0.0, 0.0]"));
    EXPECT_EQ(grids[0]["world_max"], nlohmann::json::parse("[4.5, 9.5, 2.0]"));
    EXPECT_EQ(grids[1]["world_min"], nlohmann::json::parse("[-16.0, 0.0, 0.0]"));
    EXPECT_EQ(grids[1]["voxel_size"], nlohmann::json::parse("[2.0, 2.0, 2.0]"));
    EXPECT_EQ(grids[0]["bricks"], 6);   // 10 x 20 x 5 voxels: 2 x 3 x 1 bricks of 8^3
    EXPECT_EQ(grids[0]["brick_bytes"], 6 * 9 * 9 * 9 * 4);
    EXPECT_EQ(grids[0]["up"], "y");
    r = runCli("info " + file);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("  density (index 1)  float  fog volume\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("    value range -1 .. 2\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("    bbox (world) [-16, 0, 0] -> [-2, 14, 14]\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("    up axis y (the file does not say; OpenVDB's convention)\n"), std::string::npos) << r.out;
}

// Without a terminal, --progress prints lines; Ctrl-C stops the render with exit 130 and leaves
// no file, not even a temporary.
TEST(FirstUse, ProgressLinesAndCtrlCLeaveNothingBehind) {
    const std::string dir = tempDir("interrupt");
    const std::string scene = sourceDir() + "/grids/default.json";
    CliResult r = runCli("render " + scene + " --res 8x8 --method reference --spp 4 --progress -o " + dir + "/small.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.rfind("voxlux: progress: [>                   ] reference 0/256 samples  elapsed 0m00s", 0), 0u) << r.err;
    r = runCli("render " + scene + " --res 8x8 --method reference --spp 4 -o " + dir + "/quiet.exr");
    EXPECT_EQ(r.err, "");
    fs::remove(dir + "/small.exr");
    fs::remove(dir + "/quiet.exr");

    const std::string command = voxluxBinary() + " render " + scene + " --res 256x256 --method reference --spp 4096 -o " +
                                dir + "/long.exr --preview " + dir + "/long.png 2>" + dir + "/err.txt & pid=$!; sleep 2; kill -INT $pid; "
                                "wait $pid; echo $? >" + dir + "/rc.txt";
    ASSERT_EQ(std::system(("bash -c '" + command + "'").c_str()), 0);
    EXPECT_EQ(slurp(dir + "/rc.txt"), "130\n");
    EXPECT_EQ(slurp(dir + "/err.txt"), "voxlux: interrupted: stopped before the next output; every file written is whole\n");
    fs::remove(dir + "/rc.txt");
    fs::remove(dir + "/err.txt");
    EXPECT_TRUE(fs::is_empty(dir));
}

// A quick-form sequence with a frame missing renders the others and exits 3, as a scene file does:
// its camera and choices come from the frames on disk, not from the range asked for.
TEST(FirstUse, AMissingFrameOfAQuickFormSequenceStopsOnlyThatFrame) {
    const std::string dir = tempDir("quick_missing");
    for (int f : {1, 2, 4, 5})
        fs::copy_file(sourceDir() + "/grids/cloud.vdb", dir + "/cloud.000" + std::to_string(f) + ".vdb",
                      fs::copy_options::overwrite_existing);
    const CliResult r = runCli("render " + dir + "/cloud.####.vdb --frames 1-5 --res 16x16 --backend cpu --shadows none -o " + dir +
                               "/out.####.exr");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    for (int f : {1, 2, 4, 5}) EXPECT_TRUE(fs::exists(dir + "/out.000" + std::to_string(f) + ".exr")) << f;
    EXPECT_NE(r.err.find("voxlux: error: 1 of 5 frames failed: 3\n"), std::string::npos) << r.err;
}

// What the quick form derives from a sequence is the same for any range of it: two artists'
// halves, a single frame and the whole shot get one camera, one density scale and one blackbody
// brightness, so their frames cut together.
TEST(FirstUse, BlenderFireLookIsTheSameForEveryFrameRange) {
    VOXLUX_REQUIRE_SHARED(fire, "blender/fire");
    std::vector<nlohmann::json> scenes;
    for (const char* frames : {"30", "1-60", "1-8", "31-60"}) {
        const CliResult r = runCli("scene " + fire + "/fluid_data_####.vdb --frames " + frames + " --blackbody-grid temperature");
        ASSERT_EQ(r.exit_code, 0) << r.err;
        nlohmann::json s = nlohmann::json::parse(r.out);
        s["volumes"][0].erase("frames");   // the one key that differs
        scenes.push_back(s);
        EXPECT_NE(r.err.find("camera framed on the frames on disk, 1-60, together"), std::string::npos) << r.err;
    }
    for (size_t k = 1; k < scenes.size(); ++k) EXPECT_EQ(scenes[k], scenes[0]) << k;
    EXPECT_GT(scenes[0]["volumes"][0]["material"]["density_scale"].get<double>(), 0.0);
}

// Renders frames first..last of the shared Blender fire with the quick form into `dir`.
void renderFire(const std::string& fire, const std::string& dir, const std::string& frames, const std::string& flags) {
    CliResult r = runCli("render " + fire + "/fluid_data_####.vdb --frames " + frames + " --backend cpu --blackbody-grid temperature " +
                         flags + " -o " + dir + "/fire.####.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("voxlux: quick form: up axis z (a Blender Mantaflow cache"), std::string::npos) << r.err;
}

Exr fireFrame(const std::string& dir, int frame) {
    char name[64];
    std::snprintf(name, sizeof name, "/fire.%04d.exr", frame);
    return readExr(dir + name);
}

// The shared Blender fire, as a new user renders it with the quick form.
TEST(FirstUse, BlenderFireSequenceHasOneCameraAndStandsUpright) {
    VOXLUX_REQUIRE_SHARED(fire, "blender/fire");
    const std::string dir = tempDir("fire_sequence");
    ASSERT_NO_FATAL_FAILURE(renderFire(fire, dir, "1-60", "--res 24x24 --shadows none --aovs emission"));
    const auto cameraOf = [&](int frame) { return Imf::worldToCameraAttribute(fireFrame(dir, frame).header).value(); };
    const Imath::M44f first = cameraOf(1);
    for (int frame = 2; frame <= 60; ++frame) ASSERT_EQ(cameraOf(frame), first) << "frame " << frame;

    // Upright: the plume is taller than wide in the image, and its flame (the emission) sits
    // below the smoke's centre, at the burner.
    const Exr e = fireFrame(dir, 40);
    int top = e.height, bottom = -1, left = e.width, right = -1;
    double alpha_rows = 0, alpha_sum = 0, flame_rows = 0, flame_sum = 0;
    for (int y = 0; y < e.height; ++y)
        for (int x = 0; x < e.width; ++x) {
            const size_t i = size_t(y) * e.width + x;
            const float a = e.planes.at("A")[i], flame = e.planes.at("emission.R")[i];
            if (a > 0.1f) top = std::min(top, y), bottom = std::max(bottom, y), left = std::min(left, x), right = std::max(right, x);
            alpha_rows += a * y, alpha_sum += a;
            flame_rows += flame * y, flame_sum += flame;
        }
    EXPECT_GT(bottom - top, (right - left) * 5 / 4) << "rows " << top << "-" << bottom << ", columns " << left << "-" << right;
    ASSERT_GT(flame_sum, 0.0);
    EXPECT_GT(flame_rows / flame_sum, alpha_rows / alpha_sum + 1.0);
}

// The quick form's blackbody brightness does not clip a typical Blender fire: frames 10-50 keep
// at most 1% of their pixels above 1.0.
TEST(FirstUse, BlenderFireDoesNotClip) {
    VOXLUX_REQUIRE_SHARED(fire, "blender/fire");
    const std::string dir = tempDir("fire_clip");
    ASSERT_NO_FATAL_FAILURE(renderFire(fire, dir, "10-50", "--res 48x48 --pixel-type float"));
    for (int frame = 10; frame <= 50; ++frame) {
        const Exr e = fireFrame(dir, frame);
        size_t clipped = 0, lit = 0;
        for (size_t i = 0; i < e.planes.at("R").size(); ++i) {
            const float peak = std::max({e.planes.at("R")[i], e.planes.at("G")[i], e.planes.at("B")[i]});
            clipped += peak > 1.0f;
            lit += peak > 0.01f;
        }
        EXPECT_LE(clipped, e.planes.at("R").size() / 100) << "frame " << frame;
        EXPECT_GT(lit, e.planes.at("R").size() / 50) << "frame " << frame << " is not dark";
    }
}

// The flame reads as fire: its brightness is measured on what reaches the camera through the smoke,
// so the core of the quick form's frame 30 sits near 1 in the beauty (it peaked at 0.24 when it was
// measured before the smoke absorbed it), and the flame is more than a faint base.
TEST(FirstUse, BlenderFireCoreSitsNearOne) {
    VOXLUX_REQUIRE_SHARED(fire, "blender/fire");
    const std::string dir = tempDir("fire_core");
    const CliResult r = runCli("render " + fire + "/fluid_data_0030.vdb --blackbody-grid temperature --backend cpu --res 120x160 "
                               "--pixel-type float -o " + dir + "/f.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Exr e = readExr(dir + "/f.exr");
    std::vector<float> peaks;
    for (size_t i = 0; i < e.planes.at("R").size(); ++i)
        peaks.push_back(std::max({e.planes.at("R")[i], e.planes.at("G")[i], e.planes.at("B")[i]}));
    std::sort(peaks.begin(), peaks.end());
    const float core = peaks[peaks.size() - peaks.size() / 200];   // the 99.5th percentile: the flame's core
    EXPECT_GT(core, 0.6f);
    EXPECT_LT(core, 1.6f);
    const size_t bright = size_t(std::count_if(peaks.begin(), peaks.end(), [](float p) { return p > 0.3f; }));
    EXPECT_GT(bright, peaks.size() / 100) << "the flame is a faint base";
}

}  // namespace
}  // namespace voxlux::test
