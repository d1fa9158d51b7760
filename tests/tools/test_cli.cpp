// The voxlux command line end to end: real caches render, bad input gives one line and exit 2
// and leaves no file behind, and the EXR carries the layers and metadata asked for.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <ImfHeader.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <nlohmann/json.hpp>
#include <openvdb/tools/LevelSetSphere.h>

#include "optics/blackbody.h"
#include "test_support.h"

namespace voxlux::test {
namespace {
namespace fs = std::filesystem;

// No file at `path` and no temporary file beside it.
void expectNothingWritten(const std::string& path) {
    EXPECT_FALSE(fs::exists(path)) << path;
    for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path()))
        EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

void expectRejected(const std::string& args, const std::string& message) {
    const std::string out = tempDir("rejected") + "/out.exr";
    CliResult r = runCli(args + " -o " + out);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err, "voxlux: error: " + message + "\n") << args;
    expectNothingWritten(out);
}

// Real caches render; the image is finite and not empty.
void expectRenders(const std::string& args, const std::string& name) {
    const std::string out = tempDir("real") + "/" + name + ".exr";
    CliResult r = runCli("render " + args + " --res 64x64 --backend cpu -o " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Exr e = readExr(out);
    float alpha = 0.0f;
    for (const auto& [channel, plane] : e.planes)
        for (float v : plane) ASSERT_TRUE(std::isfinite(v)) << channel;
    for (float a : e.planes["A"]) alpha = std::max(alpha, a);
    EXPECT_GT(alpha, 0.1f) << name;
}

TEST(Cli, DamagedFilesAreRefused) {
    VOXLUX_REQUIRE_SHARED(dir, "oiio/damaged");
    for (const char* name : {"bomb", "empty", "huge", "inverted", "overflow", "roundup"}) {
        const std::string file = dir + "/bad-bbox-" + name + ".vdb";
        expectRejected("render " + file, file + ": no grid named 'density' (grids: '" + name + "' (float); --grid " + name + " to render it)");
        expectRejected("render " + file + " --grid " + name, file + ": grid '" + name + "' has no active voxels");
    }
    expectRejected("render " + dir + "/truncated.vdb",
                   dir + "/truncated.vdb: truncated: grid 'huge' type needs 16 bytes at byte 77 but the file has 80");
    // info names the metadata that contradicts the voxels, and reads the voxels.
    const std::map<std::string, std::string> claims = {
        {"bomb", "[0, 0, 0] -> [200000, 200000, 200000]"}, {"huge", "[0, 0, 0] -> [1000000000, 1000000000, 1000000000]"},
        {"inverted", "[100, 100, 100] -> [-100, -100, -100]"},
        {"overflow", "[-2147483648, -2147483648, -2147483648] -> [2147483647, 2147483647, 2147483647]"},
        {"roundup", "[0, 0, 0] -> [2147483647, 8, 8]"}};
    for (const auto& [name, claim] : claims) {
        CliResult r = runCli("info " + dir + "/bad-bbox-" + name + ".vdb");
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.out.find("    damaged metadata: file_bbox " + claim + " but the voxels' bbox is empty (the metadata is ignored)\n"),
                  std::string::npos) << r.out;
    }
    CliResult r = runCli("info " + dir + "/bad-bbox-empty.vdb");   // no bbox metadata: nothing to contradict
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.find("damaged metadata"), std::string::npos) << r.out;
    r = runCli("info " + dir + "/truncated.vdb");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + dir + "/truncated.vdb: truncated: grid 'huge' type needs 16 bytes at byte 77 but the file has 80\n");
}

// OpenVDB reads a file cut short without complaint; voxlux refuses it, wherever it was cut.
TEST(Cli, TruncatedFilesAreRefused) {
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    const std::string cut = tempDir("truncated") + "/cloud.vdb";
    const auto size = fs::file_size(cloud);
    std::ifstream in(cloud, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (double share : {0.2, 0.5, 0.85, 0.999}) {
        const size_t length = size_t(double(size) * share);
        std::ofstream(cut, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(length));
        expectRejected("render " + cut, cut + ": truncated: grid 'density' ends at byte " + std::to_string(size) +
                                            " but the file has " + std::to_string(length));
        CliResult info = runCli("info " + cut);
        EXPECT_EQ(info.exit_code, 2);
    }
    VOXLUX_REQUIRE_SHARED(smoke, "arnold-usd/smoke.vdb");
    const std::string smoke_cut = tempDir("truncated") + "/smoke.vdb";
    fs::copy_file(smoke, smoke_cut, fs::copy_options::overwrite_existing);
    fs::resize_file(smoke_cut, fs::file_size(smoke) * 85 / 100);
    expectRejected("render " + smoke_cut, smoke_cut + ": truncated: grid 'density' ends at byte " +
                                              std::to_string(fs::file_size(smoke)) + " but the file has " +
                                              std::to_string(fs::file_size(smoke_cut)));
}

TEST(Cli, EmptyAndWrongGridsAreRefused) {
    VOXLUX_REQUIRE_SHARED(frame1, "openusd/smoke_000001.vdb");
    expectRejected("render " + frame1, frame1 + ": grid 'density' has no active voxels");
    expectRejected("render " + frame1 + " --grid velocity",
                   frame1 + ": grid 'velocity' (vec3s) cannot be used as density (it needs float or double values)");
    expectRejected("render " + frame1 + " --grid obstacles",
                   frame1 + ": grid 'obstacles' (int32) cannot be used as density (it needs float or double values)");
    VOXLUX_REQUIRE_SHARED(smoke, "arnold-usd/smoke.vdb");
    expectRejected("render " + smoke + " --grid dens", smoke + ": no grid named 'dens' (grids: 'density' (float); --grid density to render it)");
    expectRejected("render /nonexistent/cache.vdb", "/nonexistent/cache.vdb: no such file");
}

TEST(Cli, BlenderShadowGridIsNeverDensity) {
    VOXLUX_REQUIRE_SHARED(fire, "blender/fire/fluid_data_0030.vdb");
    expectRejected("render " + fire + " --grid shadow",
                   fire + ": grid 'shadow' has nothing visible: its 118336 active voxels are all zero or negative "
                          "(118336 negative) under the material");
    expectRenders(fire, "fire");  // the default grid name, "density"
}

TEST(Cli, MalformedSceneAndEmptyGridFileAreRefused) {
    const std::string dir = tempDir("scenes");
    const std::string scene = dir + "/broken.json";
    std::ofstream(scene) << "{\n  \"volume\": {\"path\": \"x.vdb\"\n}\n";
    expectRejected("render " + scene, scene + ": malformed JSON at line 4, column 1: unexpected end of input; "
                                              "expected '}'");
    initOpenVdb();
    const std::string empty = dir + "/empty.vdb";
    auto g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    openvdb::io::File(empty).write({g});
    expectRejected("render " + empty, empty + ": grid 'density' has no active voxels");
}

TEST(Cli, LevelSetsNeedExplicitConversion) {
    initOpenVdb();
    const std::string file = tempDir("levelset") + "/sphere.vdb";
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(0), 0.5f);
    sphere->setName("surface");
    openvdb::io::File(file).write({sphere});
    expectRejected("render " + file + " --grid surface",
                   file + ": grid 'surface' is a level set, not a fog volume; set volume.level_set to \"fog\" "
                          "(or pass --level-set fog) to convert it");
    expectRenders(file + " --grid surface --level-set fog", "levelset_fog");
}

TEST(Cli, RealCachesRender) {
    VOXLUX_REQUIRE_SHARED(smoke, "arnold-usd/smoke.vdb");
    VOXLUX_REQUIRE_SHARED(cloud, "disney-wdas-cloud/wdas_cloud_sixteenth.vdb");
    VOXLUX_REQUIRE_SHARED(heat, "openusd/densityAndHeat.vdb");
    VOXLUX_REQUIRE_SHARED(torus, "arnold-usd/torus01.vdb");
    expectRenders(smoke, "smoke");
    expectRenders(cloud + " --density-scale 0.5", "cloud");
    expectRenders(heat + " --emission-grid heat --aovs emission", "heat");
    expectRenders(torus + " --grid voxel_fog_density", "torus");
}

// --emission-grid and --blackbody-grid replace the scene's emission list with one source each.
TEST(Cli, EmissionQuickForms) {
    initOpenVdb();
    const std::string file = tempDir("emission_cli") + "/fire.vdb";
    auto density = boxGrid({0, 0, 0}, {15, 15, 15}, 0.5f);
    auto heat = boxGrid({4, 4, 4}, {11, 11, 11}, 2.0f);
    heat->setName("temperature");
    openvdb::io::File(file).write({density, heat});
    CliResult r = runCli("scene " + file + " --emission-grid temperature --blackbody-grid temperature");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto emission = nlohmann::json::parse(r.out)["volumes"][0]["emission"];
    ASSERT_EQ(emission.size(), 2u);
    EXPECT_EQ(emission[0], nlohmann::json::parse(
                               R"({"grid": "temperature", "kind": "constant", "color": [1, 1, 1], "intensity": 1})"));
    // The quick form scales the blackbody so the brightest columns reach the camera at 1 through
    // the smoke: the heat box is 8 voxels of 1 unit deep at 2000 K (luminance Planck's ratio to
    // 1500 K's), behind 4 voxels of the density box. The density box's median column holds 16 x 0.5,
    // scaled to an optical depth of 2: tau = 0.125 a voxel, 0.5 in front of the heat, and the 8
    // voxels of heat sum to ratio x e^-0.5 x (1 - e^-(8 tau)) / tau.
    const double ratio = blackbodyXYZ(2000.0).y / blackbodyXYZ(1500.0).y;
    const double reaching = ratio * std::exp(-0.5) * (1.0 - std::exp(-1.0)) / 0.125;
    EXPECT_NEAR(emission[1]["intensity"].get<double>(), 1.0 / reaching, 1e-4 / reaching);
    emission[1].erase("intensity");
    EXPECT_EQ(emission[1], nlohmann::json::parse(R"({"grid": "temperature", "kind": "blackbody",
        "temperature_scale": 1000, "temperature_offset": 0, "cutoff": 1000, "normalization": "physical",
        "reference_temperature": 1500})"));
    r = runCli("render " + file + " --blackbody-grid temperature --explain -o " + file + ".exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("reads density 'density', emission 'temperature' from " + file), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(", emission: blackbody from 'temperature'  [after:"), std::string::npos) << r.out;
    expectRenders(file + " --blackbody-grid temperature --aovs emission", "blackbody");
}

TEST(Cli, InfoListsGridsAndBricks) {
    VOXLUX_REQUIRE_SHARED(fire, "blender/fire/fluid_data_0030.vdb");
    CliResult r = runCli("info " + fire);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(fire + ": 5 grids\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  shadow  float  fog volume\n    active voxels 118336 (200 active tiles)\n"
                         "    bbox (index) [0, 0, 0] -> [42, 42, 63]  (43 x 43 x 64)\n"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("  velocity  vec3s"), std::string::npos);
}

TEST(Cli, InfoAsJson) {
    CliResult r = runCli("info --json " + sourceDir() + "/grids/cloud.vdb");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["grids"].size(), 1u);
    const auto& g = j["grids"][0];
    EXPECT_EQ(g["name"], "density");
    EXPECT_EQ(g["type"], "float");
    EXPECT_EQ(g["class"], "fog volume");
    EXPECT_GT(g["active_voxels"].get<int>(), 50000);
    EXPECT_GT(g["bricks"].get<int>(), 100);
    EXPECT_NEAR(g["voxel_size"][0].get<double>(), 2.0 / 96.0, 1e-9);
    EXPECT_EQ(g["bbox_min"].size(), 3u);
}

TEST(Cli, ExplainShowsThePlan) {
    // The quick form: one key light, ray-marched shadows.
    CliResult r = runCli("render " + sourceDir() + "/grids/cloud.vdb --explain -o x.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("run   load"), std::string::npos);
    EXPECT_NE(r.out.find("run   march             1 light, ray-marched shadow rays per sample (reference)  [after: "
                         "color_space brick classify volumes camera holdouts empty_check light_cache propagation eye_pass; reads: "
                         "/render/resolution /render/step /render/shadow_step /render/transmittance_cutoff /render/filter /render/backend "
                         "/render/method /render/reference /render/motion_blur /render/region /volumes/*/material"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("skip  light_cache       skipped: no effect in the scene needs a precomputed light cache"),
              std::string::npos);
    EXPECT_NE(r.out.find("skip  grade"), std::string::npos);

    r = runCli("render " + sourceDir() + "/grids/cloud_sat.json --explain");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("run   light_grid        extinction box-filtered into a 128-cell light grid over the occupied bricks"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("run   light_cache       ambient occlusion, 5 shells, 1 shadow cone of 20 cuboids (2 deg)"),
              std::string::npos)
        << r.out;
    r = runCli("render " + sourceDir() +
               "/grids/cloud_sat.json --explain --light directional:dir=0,-1,0 --set effects.color_bleeding=1");
    EXPECT_NE(r.out.find("ambient_occlusion is on but no ambient light is in the scene"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("color_bleeding needs ambient occlusion"), std::string::npos) << r.out;

    r = runCli("render " + sourceDir() + "/grids/cloud_propagation.json --explain");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("run   propagation       1 light swept along the closest axis; direct RGB, indirect RGB blurred "
                         "in a 30 deg cone over 9 taps, transport colour (0.8, 0.6, 0.45), perturbed"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("run   march             1 light, direct and indirect light read from the illumination volume, "
                         "noise-perturbed"),
              std::string::npos)
        << r.out;
    r = runCli("render " + sourceDir() + "/grids/default.json --explain --shadows raymarch");
    EXPECT_NE(r.out.find("skip  illumination_grid skipped: no effect in the scene needs an illumination volume (indirect light "
                         "needs effects.shadows = propagation)"),
              std::string::npos)
        << r.out;
}

// The SAT scene end to end through the CLI: the light passes run, the ambient AOV is written.
TEST(Cli, SatSceneRendersWithAmbientLayer) {
    const std::string dir = tempDir("sat_cli");
    CliResult r = runCli("render " + sourceDir() + "/grids/cloud_sat.json --backend cpu --res 80x50 -o " +
                         dir + "/sat.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Stage times print as "  <stage> 0.012 s" (the output path contains "sat" too).
    for (const char* stage : {"light_grid", "sat", "light_cache"})
        EXPECT_NE(r.out.find("  " + std::string(stage) + " "), std::string::npos) << stage << " in " << r.out;
    Exr exr = readExr(dir + "/sat.exr");
    const auto& ambient = exr.planes["ambient.B"];
    EXPECT_GT(*std::max_element(ambient.begin(), ambient.end()), 0.0f);
}

TEST(Cli, SceneCommandReproducesTheQuickForm) {
    const std::string dir = tempDir("quick");
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    CliResult scene = runCli("scene " + cloud + " --res 40x30 --shadows none --density-scale 30");
    ASSERT_EQ(scene.exit_code, 0) << scene.err;
    std::ofstream(dir + "/scene.json") << scene.out;
    ASSERT_EQ(runCli("render " + cloud + " --res 40x30 --shadows none --density-scale 30 --backend cpu -o " + dir +
                     "/quick.exr").exit_code, 0);
    ASSERT_EQ(runCli("render " + dir + "/scene.json --backend cpu -o " + dir + "/scene.exr").exit_code, 0);
    Exr a = readExr(dir + "/quick.exr"), b = readExr(dir + "/scene.exr");
    EXPECT_EQ(a.planes["R"], b.planes["R"]);
    EXPECT_EQ(a.planes["A"], b.planes["A"]);
    EXPECT_GT(*std::max_element(a.planes["A"].begin(), a.planes["A"].end()), 0.5f);
}

TEST(Cli, ExrHasRequestedLayersAndMetadata) {
    const std::string dir = tempDir("exr");
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    CliResult r = runCli("render " + cloud + " --res 32x24 --backend cpu --aovs direct,depth --pixel-type float "
                         "--density-scale 30 --stats " + dir + "/stats.json -o " + dir + "/a.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Exr e = readExr(dir + "/a.exr");
    std::vector<std::string> expected{"A", "B", "G", "R", "depth.Z", "direct.B", "direct.G", "direct.R"};
    EXPECT_EQ(e.channels, expected);
    EXPECT_EQ(e.width, 32);
    EXPECT_EQ(e.height, 24);
    EXPECT_TRUE(Imf::hasWorldToCamera(e.header));
    EXPECT_TRUE(Imf::hasWorldToNDC(e.header));
    EXPECT_EQ(e.header.typedAttribute<Imf::StringAttribute>("voxlux/version").value(), VOXLUX_VERSION);
    EXPECT_EQ(e.header.typedAttribute<Imf::StringAttribute>("voxlux/sceneHash").value().size(), 16u);
    EXPECT_NE(e.header.find("voxlux/seconds/march"), e.header.end());
    EXPECT_EQ(e.header.compression(), Imf::ZIP_COMPRESSION);
    // Premultiplied: where nothing is hit, colour and alpha are both 0; direct == beauty here.
    for (size_t i = 0; i < e.planes["R"].size(); ++i) {
        EXPECT_FLOAT_EQ(e.planes["R"][i], e.planes["direct.R"][i]);
        if (e.planes["A"][i] == 0.0f) {
            EXPECT_EQ(e.planes["R"][i], 0.0f);
        }
    }
    std::ifstream statsFile(dir + "/stats.json");
    auto stats = nlohmann::json::parse(statsFile);
    EXPECT_EQ(stats["backend"], "cpu");
    EXPECT_GT(stats["peak_rss_bytes"].get<double>(), 0.0);
    for (const char* stage : {"load", "brick", "classify", "march", "write"})
        EXPECT_TRUE(stats["frames"][0]["stages"].contains(stage)) << stage;
}

// Input that used to exit 1 ("internal error"): a path the system refuses and a light edit whose
// type is not a string are bad input; a file name that is not UTF-8 is a file name.
TEST(Cli, OddPathsAndMistypedEditsAreNeverInternalErrors) {
    const std::string dir = tempDir("bad_input");
    const std::string long_path = dir + "/" + std::string(5000, 'a') + ".vdb";
    expectRejected("render " + long_path, long_path + ": File name too long");
    std::ofstream(dir + "/edit.json") << R"({"edits": [{"light": 0, "set": {"type": 5}}]})";
    // File names are bytes: a Latin-1 name (not UTF-8) renders, keys and hashes escape it.
    const std::string latin1 = dir + "/caf\xe9";
    fs::copy_file(sourceDir() + "/grids/cloud.vdb", latin1 + ".vdb");
    const CliResult r = runCli("render '" + latin1 + ".vdb' --res 16x16 --backend cpu --shadows none -o '" + latin1 + ".exr'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(latin1 + ".exr"));
    expectRejected("render " + sourceDir() + "/grids/cloud_multilight.json --res 16x16 --light-edit " + dir +
                       "/edit.json",
                   dir + "/edit.json: /edits/0/set/type: expected a string, got number");
}

// A frame's outputs are all written or none is: a preview or stats file that cannot be written
// leaves no EXR behind (it used to exit 2 with the EXR written).
TEST(Cli, AnOutputThatCannotBeWrittenLeavesNoOther) {
    const std::string dir = tempDir("all_or_none");
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    std::ofstream(dir + "/a_file") << "not a folder";
    const std::string args = "render " + cloud + " --res 16x16 --backend cpu --shadows none -o " + dir + "/out.exr";
    CliResult r = runCli(args + " --preview " + dir + "/a_file/preview.png");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + dir + "/a_file/preview.png: cannot create folder " + dir + "/a_file: Not a directory\n");
    EXPECT_FALSE(fs::exists(dir + "/out.exr"));
    r = runCli(args + " --stats " + dir + "/a_file/stats.json");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + dir + "/a_file/stats.json: cannot create folder " + dir + "/a_file: Not a directory\n");
    EXPECT_FALSE(fs::exists(dir + "/out.exr"));
    // The preview goes when the EXR cannot be written.
    r = runCli("render " + cloud + " --res 16x16 --backend cpu --shadows none -o " + dir + "/a_file/out.exr --preview " + dir +
               "/preview.png");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_FALSE(fs::exists(dir + "/preview.png"));
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"a_file"});
}

// A range is never walked frame by frame: with 2e9 frames and one file on disk, the missing frames
// are named in one line from one listing of the folder, frame 1 renders, and the run exits 3;
// --fail-fast stops before any frame.
TEST(Cli, AHugeFrameRangeNamesItsMissingFramesInOneLine) {
    const std::string dir = tempDir("huge_range");
    fs::copy_file(sourceDir() + "/grids/cloud.vdb", dir + "/cloud.0001.vdb", fs::copy_options::overwrite_existing);
    const std::string command = "render " + dir + "/cloud.####.vdb --frames 1-2000000000 --res 16x16 --backend cpu --shadows none -o " +
                                dir + "/out.####.exr";
    CliResult r = runCli(command + " --fail-fast");
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_EQ(linesStartingWith(r.err, "voxlux: error: "), "voxlux: error: frames 2-2000000000 of 1-2000000000 are not on disk (" + dir + "/cloud.0002.vdb: no such file)\n"
                     "voxlux: error: 1999999999 of 2000000000 frames failed: 2-2000000000 (stopped there, --fail-fast; 1 not rendered)\n");
    EXPECT_FALSE(fs::exists(dir + "/out.0001.exr"));
    r = runCli(command);
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_EQ(linesStartingWith(r.err, "voxlux: error: "),
              "voxlux: error: frames 2-2000000000 of 1-2000000000 are not on disk (" + dir + "/cloud.0002.vdb: no such file); the others render\n"
              "voxlux: error: 1999999999 of 2000000000 frames failed: 2-2000000000\n");
    EXPECT_TRUE(fs::exists(dir + "/out.0001.exr"));
    // No frame of the range on disk at all: one line, exit 2, nothing written.
    r = runCli("render " + dir + "/cloud.####.vdb --frames 5-9 -o " + dir + "/none.####.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + dir + "/cloud.####.vdb: no file of frames 5-9 exists (on disk: frames 1)\n");
    // Frame numbers beyond 32 bits have no int value and are refused.
    r = runCli("render " + dir + "/cloud.####.vdb --frames 1-3000000000 -o " + dir + "/out.####.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --frames 1-3000000000: /volumes/0/frames: expected FIRST-LAST[xSTEP] or a list of them, e.g. 1-240x2,300\n");
}

// An output folder that cannot take a file stops a sequence in one line before its first frame
// (exit 2), naming the folder and the cause on the user's path, never a temporary file; the
// preview's, --stats' and --log-json's folders too; --explain lists the same line.
TEST(Cli, AnUnwritableOutputStopsTheRunBeforeTheFirstFrame) {
    ReadOnlyFolder ro("unwritable_output");
    if (!ro.problem.empty()) GTEST_SKIP() << ro.problem;
    const std::string dir = tempDir("unwritable_frames");
    for (const char* f : {"0001", "0002"})
        fs::copy_file(sourceDir() + "/grids/cloud.vdb", dir + "/cloud." + f + ".vdb", fs::copy_options::overwrite_existing);
    const std::string args = "render " + dir + "/cloud.####.vdb --frames 1-2 --res 16x16 --backend cpu --shadows none";
    const std::map<std::string, std::string> cases = {
        {" -o " + ro.path + "/sub/f.####.exr", ro.path + "/sub/f.0001.exr: cannot create folder " + ro.path + "/sub: " + ro.cause},
        {" -o " + ro.path + "/f.####.exr", ro.path + "/f.0001.exr: cannot write in folder " + ro.path + ": " + ro.cause},
        {" -o " + dir + "/f.####.exr --preview " + ro.path + "/p.####.png", ro.path + "/p.0001.png: cannot write in folder " + ro.path + ": " + ro.cause},
        {" -o " + dir + "/f.####.exr --stats " + ro.path + "/s/stats.json", ro.path + "/s/stats.json: cannot create folder " + ro.path + "/s: " + ro.cause},
        {" -o " + dir + "/f.####.exr --log-json " + ro.path + "/log.jsonl", ro.path + "/log.jsonl: cannot write in folder " + ro.path + ": " + ro.cause}};
    for (const auto& [flags, message] : cases) {
        CliResult r = runCli(args + flags);
        EXPECT_EQ(r.exit_code, 2) << flags;
        EXPECT_EQ(r.err, "voxlux: error: " + message + "\n") << flags;
        EXPECT_EQ(r.out, "") << flags;   // no frame rendered
        r = runCli(args + flags + " --explain");
        EXPECT_EQ(r.exit_code, 2) << flags;
        EXPECT_NE(r.out.find("cannot render:\n  " + message + "\n"), std::string::npos) << r.out;
    }
    EXPECT_FALSE(fs::exists(dir + "/f.0001.exr"));
}

TEST(Cli, AWordThatIsNoCommandIsNamed) {
    const CliResult r = runCli("bogus cache.vdb");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: command line: 'bogus' is not a command (render, scene, info, import, study, calibrate, view, farm, "
                     "make-cloud, make-sky)\n");
}

// make-sky writes a float lat-long map an environment light takes as it is; a resolution that is
// not twice as wide as high is refused by name, and nothing is written.
TEST(Cli, MakeSkyWritesAMapAnEnvironmentLightTakes) {
    const std::string dir = tempDir("make_sky");
    CliResult r = runCli("make-sky -o " + dir + "/sky.exr --kind sunset --res 64x32");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, "wrote " + dir + "/sky.exr (64x32, ACEScg, sun at 3 degrees, toward (0.998, 0.000, 0.052) with up z)\n");
    const Exr sky = readExr(dir + "/sky.exr");
    EXPECT_EQ(sky.width, 64);
    EXPECT_EQ(sky.height, 32);
    r = runCli("render " + sourceDir() + "/grids/cloud.vdb --res 24x16 -o " + dir + "/lit.exr --set 'lights=[{\"type\":\"environment\",\"map\":\"" + dir +
               "/sky.exr\",\"up\":\"z\"}]'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    r = runCli("make-sky -o " + dir + "/wide.exr --res 64x64");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --res: '64x64' is not WIDTHxHEIGHT with the width twice the height (2 to 8192 rows)\n");
    EXPECT_FALSE(fs::exists(dir + "/wide.exr"));
}

// Standard output holds results (the frames written, a scene, a graph); the quick form's notes
// go to standard error for every command. The "wrote" line names every file a frame wrote.
TEST(Cli, NotesGoToStandardErrorAndWroteNamesEveryFile) {
    const std::string dir = tempDir("notes_and_wrote");
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    CliResult r = runCli("render " + cloud + " --res 16x16 --backend cpu --shadows none --deep -o " + dir + "/a.exr --preview " + dir + "/a.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.rfind("wrote " + dir + "/a.exr, " + dir + "/a.deep.exr and " + dir + "/a.png (cpu, ", 0), 0u) << r.out;
    EXPECT_EQ(r.out.find("quick form"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("voxlux: quick form: density_scale "), std::string::npos) << r.err;
    r = runCli("render " + cloud + " --explain -o " + dir + "/b.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.find("quick form"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("voxlux: quick form: up axis y"), std::string::npos) << r.err;
}

// --threads 1 (and VOXLUX_THREADS=1) keeps a render on one core: its CPU time stays within 1.1x of
// its wall time, where all cores of this machine would take more. Bad values are refused.
TEST(Cli, ThreadsOneKeepsARenderOnOneCore) {
    const std::string dir = tempDir("threads");
    const std::string render = voxluxBinary() + " render " + sourceDir() +
                               "/grids/default.json --res 96x64 --backend cpu --method reference --spp 64 -o " + dir + "/t.exr";
    for (const std::string& command : {render + " --threads 1", "VOXLUX_THREADS=1 " + render}) {
        rusage before{}, after{};
        getrusage(RUSAGE_CHILDREN, &before);
        const auto start = std::chrono::steady_clock::now();
        ASSERT_EQ(std::system((command + " >/dev/null 2>&1").c_str()), 0) << command;
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        getrusage(RUSAGE_CHILDREN, &after);
        const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
        const double cpu = seconds(after.ru_utime) - seconds(before.ru_utime) + seconds(after.ru_stime) - seconds(before.ru_stime);
        ASSERT_GT(wall, 0.3) << command << ": too short to measure";
        EXPECT_LE(cpu, 1.1 * wall) << command << ": " << cpu << " s of CPU in " << wall << " s";
    }
    CliResult r = runCli("render " + sourceDir() + "/grids/default.json --threads 0 -o " + dir + "/x.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --threads 0: must be 1 or more\n");
    r = runShell("VOXLUX_THREADS=many " + voxluxBinary() + " render " + sourceDir() + "/grids/default.json -o " +
                 dir + "/x.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: VOXLUX_THREADS='many': expected a number of threads, 1 or more\n");
    EXPECT_FALSE(fs::exists(dir + "/x.exr"));
}

TEST(Cli, SequenceWithAnEmptyFrameRendersItTransparent) {
    VOXLUX_REQUIRE_SHARED(frame1, "openusd/smoke_000001.vdb");
    const std::string dir = tempDir("sequence");
    const std::string pattern = fs::path(frame1).parent_path().string() + "/smoke_######.vdb";
    CliResult r = runCli("render " + pattern + " --frames 1-3 --res 24x24 --backend cpu --shadows none -o " + dir +
                         "/seq.####.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("voxlux: warning: 1 empty frame(s) rendered transparent"), std::string::npos) << r.err;
    for (const char* f : {"0001", "0002", "0003"}) EXPECT_TRUE(fs::exists(dir + "/seq." + f + ".exr")) << f;
    Exr first = readExr(dir + "/seq.0001.exr");
    for (float a : first.planes["A"]) ASSERT_EQ(a, 0.0f);
}

}  // namespace
}  // namespace voxlux::test

namespace voxlux::test {
namespace {

TEST(Cli, RepeatedGridNamesArePickedByIndexWithAWarning) {
    VOXLUX_REQUIRE_SHARED(grids, "arnold-usd/grids.vdb");
    const std::string dir = tempDir("repeated");
    CliResult first = runCli("render " + grids + " --res 32x32 --backend cpu --shadows none -o " + dir + "/0.exr");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    EXPECT_EQ(first.err.substr(0, first.err.find('\n') + 1),
              "voxlux: warning: " + grids + ": 3 grids are named 'density'; using index 0 (set the grid's \"index\" to choose)\n");
    CliResult third = runCli("render " + grids + " --grid-index 2 --res 32x32 --backend cpu --shadows none -o " + dir +
                             "/2.exr");
    ASSERT_EQ(third.exit_code, 0) << third.err;
    EXPECT_NE(third.err.find("using index 2"), std::string::npos);
    // The three grids differ (491 and 803 active voxels), so the framed images differ.
    EXPECT_NE(readExr(dir + "/0.exr").planes["A"], readExr(dir + "/2.exr").planes["A"]);
    expectRejected("render " + grids + " --grid-index 3",
                   grids + ": grid index 3 for 'density' is out of range (the file has 3)");
}

TEST(Cli, BadOptionsAreRefusedWithTheOptionNamed) {
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    expectRejected("render " + cloud + " --res 512", "--res 512: expected WIDTHxHEIGHT");
    expectRejected("render " + cloud + " --res 0x10", "--res 0x10: /render/resolution: expected [width, height], integers in 1..16384");
    // Past int's range: converted to int before the check, it was undefined (fuzz_cli_specs found it).
    expectRejected("render " + cloud + " --res 1920x18888888080",
                   "--res 1920x18888888080: /render/resolution: expected [width, height], integers in 1..16384");
    expectRejected("render " + cloud + " --set effects.cone.samples", "--set 'effects.cone.samples': expected KEY=VALUE");
    expectRejected("render " + cloud + " --set effects.cone.samples=0",
                   "--set 'effects.cone.samples=0': /effects/cone/samples: must lie in 1..1024");
    expectRejected("render " + cloud + " --step 0", "--step: /render/step: must lie in [0.01, 64] voxels");
    expectRejected("render " + cloud + " --shadows sat", "--shadows: /effects/shadows: 'sat' is not one of none, raymarch, sat_cone, propagation");
    expectRejected("render " + cloud + " --aovs direct,depth,direct",
                   "--aovs: /output/aovs/2: duplicate AOV 'direct' (first at /output/aovs/0)");
}

// A light from the command line is read by the scene's light reader, so it gets exactly the
// scene's checks, and its errors name the flag.
TEST(Cli, LightFlagsGetTheScenesChecks) {
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    expectRejected("render " + cloud + " --light area:pos=0,0,0",
                   "--light 'area:pos=0,0,0': /type: 'area' is not one of directional, point, spot, ambient, environment");
    expectRejected("render " + cloud + " --light ambient:dir=0,1,0",
                   "--light 'ambient:dir=0,1,0': /direction: unknown key (expected one of name, enabled, type, color, intensity, group)");
    expectRejected("render " + cloud + " --light point:intensity=5", "--light 'point:intensity=5': /position: required key is missing");
    // A zero direction overflowed an int in the march's brick walk.
    expectRejected("render " + cloud + " --light directional:dir=0,0,0", "--light 'directional:dir=0,0,0': /direction: must not be zero");
    expectRejected("render " + cloud + " --light point:pos=0,3,0:intensity=-1",
                   "--light 'point:pos=0,3,0:intensity=-1': /intensity: must be a finite number >= 0");
    expectRejected("render " + cloud + " --light point:pos=0,3,0:color=-1,1,1",
                   "--light 'point:pos=0,3,0:color=-1,1,1': /color: must be finite and >= 0");
    expectRejected("render " + cloud + " --light spot:pos=0,3,0:dir=0,-1,0:angle=90",
                   "--light 'spot:pos=0,3,0:dir=0,-1,0:angle=90': /cone_angle: must lie in (0, 90) degrees");
    expectRejected("render " + cloud + " --light point:pos=2e9,0,0", "--light 'point:pos=2e9,0,0': /position: each coordinate must lie within +-1e9");
}

// Numbers that have no value in the scene are refused, never turned into the default or wrapped.
TEST(Cli, NonFiniteAndOutOfRangeNumbersAreRefused) {
    const std::string cloud = sourceDir() + "/grids/cloud.vdb";
    expectRejected("render " + cloud + " --step nan", "--step: nan is not a finite number");
    expectRejected("render " + cloud + " --density-scale inf", "--density-scale: inf is not a finite number");
    expectRejected("render " + cloud + " --set effects.cone.samples=4294967316",
                   "--set 'effects.cone.samples=4294967316': /effects/cone/samples: 4294967316 is beyond the int range");
    expectRejected("render " + cloud + " --set render.reference.spp=4294967297",
                   "--set 'render.reference.spp=4294967297': /render/reference/spp: 4294967297 is beyond the int range");
    expectRejected("render " + cloud + " --set material.density_scale=1e39",
                   "--set 'material.density_scale=1e39': /volumes/0/material/density_scale: 1e+39 is beyond the float range (+-3.4e38)");
    // null is not a value: it never reads as the default.
    expectRejected("render " + cloud + " --set render.step=null", "--set 'render.step=null': /render/step: expected a number, got null");
    // CLI11's own conversion errors are bad input too: exit 2, one line.
    expectRejected("render " + cloud + " --step abc", "command line: Could not convert: --step = abc");
}


}  // namespace
}  // namespace voxlux::test
