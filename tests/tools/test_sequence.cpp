// `voxlux render` over frames as a farm runs it: frame specs, --resume against the EXR's scene
// hash, failed frames named with exit 3 while the others render, --fail-fast, the JSON log, and
// the progress bar's stage on a terminal.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <ImfStringAttribute.h>
#include <nlohmann/json.hpp>

#include "test_support.h"
#include "tools/sequence_render.h"

namespace voxlux::test {
namespace {
namespace fs = std::filesystem;

// Four frames of the bundled cloud, cloud.0001.vdb .. cloud.0004.vdb, in a fresh folder.
std::string cloudFrames(const std::string& name) {
    const std::string dir = tempDir(name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const char* f : {"0001", "0002", "0003", "0004"})
        fs::copy_file(sourceDir() + "/grids/cloud.vdb", dir + "/cloud." + f + ".vdb");
    return dir;
}

std::string renderArgs(const std::string& dir, const std::string& frames) {
    return "render " + dir + "/cloud.####.vdb --frames " + frames + " --frame-on 1 --res 16x16 --backend cpu --shadows none -o " + dir +
           "/out.####.exr";
}

std::string sceneHashOf(const std::string& exr) {
    return readExr(exr).header.typedAttribute<Imf::StringAttribute>("voxlux/sceneHash").value();
}

std::vector<nlohmann::json> logLines(const std::string& path) {
    std::vector<nlohmann::json> lines;
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
    return lines;
}

size_t countOf(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

// A chunk rendered alone carries the hash of the whole sequence's frames, so a resumed run skips
// it; a frame cut short, and every frame once the scene changes, renders again.
TEST(Sequence, ResumeSkipsDoneFramesAndRendersTheRest) {
    const std::string dir = cloudFrames("resume");
    CliResult chunk = runCli(renderArgs(dir, "1-2"));
    ASSERT_EQ(chunk.exit_code, 0) << chunk.err;
    const auto first_written = fs::last_write_time(dir + "/out.0001.exr");
    fs::resize_file(dir + "/out.0002.exr", fs::file_size(dir + "/out.0002.exr") / 2);

    CliResult resumed = runCli(renderArgs(dir, "1-4") + " --resume --log-json " + dir + "/log.jsonl");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_NE(resumed.out.find("skipped frame 1: " + dir + "/out.0001.exr is done\n"), std::string::npos) << resumed.out;
    EXPECT_EQ(countOf(resumed.out, "wrote "), 3u) << resumed.out;
    EXPECT_NE(resumed.out.find("resumed: 1 of 4 frames were done and skipped\n"), std::string::npos);
    EXPECT_EQ(fs::last_write_time(dir + "/out.0001.exr"), first_written);
    EXPECT_EQ(sceneHashOf(dir + "/out.0001.exr"), sceneHashOf(dir + "/out.0004.exr"));
    // The same cloud in every frame: the re-rendered frame equals the one kept.
    EXPECT_EQ(readExr(dir + "/out.0002.exr").planes, readExr(dir + "/out.0001.exr").planes);

    const std::vector<nlohmann::json> log = logLines(dir + "/log.jsonl");
    ASSERT_EQ(log.size(), 4u);
    EXPECT_EQ(log[0]["status"], "skipped");
    EXPECT_EQ(log[0]["frame"], 1);
    for (int k = 1; k < 4; ++k) {
        EXPECT_EQ(log[k]["status"], "rendered");
        EXPECT_EQ(log[k]["frame"], k + 1);
        EXPECT_EQ(log[k]["path"], dir + "/out.000" + std::to_string(k + 1) + ".exr");
        EXPECT_GT(log[k]["seconds"].get<double>(), 0.0);
        EXPECT_TRUE(log[k]["stages"].contains("march"));
    }
    // Later frames reuse what the frame change left valid: the colour transforms.
    EXPECT_EQ(log[3]["reused"], nlohmann::json::array({"color_space", "color_transforms"}));

    const std::string hash = sceneHashOf(dir + "/out.0001.exr");
    CliResult other = runCli(renderArgs(dir, "1-4") + " --density-scale 3 --resume");
    ASSERT_EQ(other.exit_code, 0) << other.err;
    EXPECT_EQ(countOf(other.out, "wrote "), 4u) << other.out;
    EXPECT_NE(sceneHashOf(dir + "/out.0001.exr"), hash);
}

// A missing and a corrupt frame fail on their own: each is named, the others render, and the
// exit code is 3 with the failed frames listed. --fail-fast stops at the first.
TEST(Sequence, FailedFramesAreNamedAndTheOthersRender) {
    const std::string dir = cloudFrames("failed_frames");
    fs::remove(dir + "/cloud.0002.vdb");
    { std::ofstream(dir + "/cloud.0003.vdb", std::ios::trunc) << "not a vdb"; }
    CliResult r = runCli(renderArgs(dir, "1-4") + " --log-json " + dir + "/log.jsonl");
    EXPECT_EQ(r.exit_code, 3);
    // A frame not on disk is named before any frame renders; a damaged one when its turn comes.
    EXPECT_EQ(r.err.rfind("voxlux: error: frames 2 of 1-4 are not on disk (" + dir + "/cloud.0002.vdb: no such file); the others render\n", 0), 0u)
        << r.err;
    EXPECT_NE(r.err.find("voxlux: error: frame 3: " + dir + "/cloud.0003.vdb: "), std::string::npos) << r.err;
    const std::string errors = linesStartingWith(r.err, "voxlux: error: ");
    EXPECT_EQ(errors.substr(errors.rfind("voxlux: error: ")), "voxlux: error: 2 of 4 frames failed: 2-3\n");
    EXPECT_TRUE(fs::exists(dir + "/out.0001.exr"));
    EXPECT_TRUE(fs::exists(dir + "/out.0004.exr"));
    EXPECT_FALSE(fs::exists(dir + "/out.0002.exr"));
    const std::vector<nlohmann::json> log = logLines(dir + "/log.jsonl");
    ASSERT_EQ(log.size(), 4u);
    EXPECT_EQ(log[0]["status"], "missing");
    EXPECT_EQ(log[0]["frames"], "2");
    EXPECT_EQ(log[0]["error"], "frames 2 of 1-4 are not on disk (" + dir + "/cloud.0002.vdb: no such file)");
    EXPECT_EQ(log[1]["status"], "rendered");
    EXPECT_EQ(log[2]["status"], "failed");
    EXPECT_EQ(log[2]["frame"], 3);
    EXPECT_EQ(log[3]["status"], "rendered");

    // --fail-fast stops before the first frame when one is not on disk, and at a damaged one.
    fs::remove(dir + "/out.0004.exr");
    r = runCli(renderArgs(dir, "1-4") + " --fail-fast");
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_EQ(linesStartingWith(r.err, "voxlux: error: "), "voxlux: error: frames 2 of 1-4 are not on disk (" + dir + "/cloud.0002.vdb: no such file)\n"
                     "voxlux: error: 1 of 4 frames failed: 2 (stopped there, --fail-fast; 3 not rendered)\n");
    EXPECT_FALSE(fs::exists(dir + "/out.0004.exr"));
    r = runCli(renderArgs(dir, "3-4") + " --fail-fast");
    EXPECT_EQ(r.exit_code, 3);
    const std::string stopped = linesStartingWith(r.err, "voxlux: error: ");
    EXPECT_EQ(stopped.substr(stopped.rfind("voxlux: error: ")), "voxlux: error: 1 of 2 frames failed: 3 (stopped there, --fail-fast; 1 not rendered)\n");
    EXPECT_FALSE(fs::exists(dir + "/out.0004.exr"));
}

// A damaged file among the frames on disk, outside the range asked for, stops nothing: the frames
// asked for render, and a note names it. A frame number in a folder's name is looked up frame by
// frame, as no one folder lists the frames.
TEST(Sequence, ADamagedFrameOutsideTheRangeAndAFrameFolderRender) {
    const std::string dir = cloudFrames("damaged_outside");
    { std::ofstream(dir + "/cloud.0004.vdb", std::ios::trunc) << "half written"; }
    CliResult r = runCli("render " + dir + "/cloud.####.vdb --frames 1-2 --res 16x16 --backend cpu --shadows none -o " + dir + "/out.####.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("voxlux: frames 4 on disk cannot be read and are left out of what the data decides (" + dir + "/cloud.0004.vdb: "),
              std::string::npos) << r.err;
    for (int f : {1, 2}) {
        fs::create_directories(dir + "/f_000" + std::to_string(f));
        fs::copy_file(dir + "/cloud.0001.vdb", dir + "/f_000" + std::to_string(f) + "/density.vdb", fs::copy_options::overwrite_existing);
    }
    r = runCli("render " + dir + "/f_####/density.vdb --frames 1-3 --res 16x16 --backend cpu --shadows none -o " + dir + "/folder.####.exr");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(fs::exists(dir + "/folder.0001.exr") && fs::exists(dir + "/folder.0002.exr"));
    EXPECT_NE(r.err.find("voxlux: error: frames 3 of 1-3 are not on disk (" + dir + "/f_0003/density.vdb: no such file); the others render\n"),
              std::string::npos) << r.err;
}

// The time left comes from the frames' own times: a simulation whose frames grow by a second each
// is extended along its line, not by the mean of its first frames.
TEST(Sequence, TimeLeftFollowsTheFramesTimes) {
    EXPECT_DOUBLE_EQ(sequenceSecondsLeft({}, 5), 0.0);
    EXPECT_DOUBLE_EQ(sequenceSecondsLeft({2.0}, 5), 10.0);
    EXPECT_DOUBLE_EQ(sequenceSecondsLeft({1.0, 3.0}, 2), 6.0);          // the last frame's time, until three
    EXPECT_DOUBLE_EQ(sequenceSecondsLeft({1.0, 2.0, 3.0, 4.0}, 3), 5.0 + 6.0 + 7.0);
    EXPECT_DOUBLE_EQ(sequenceSecondsLeft({2.0, 2.0, 2.0}, 4), 8.0);
    EXPECT_DOUBLE_EQ(sequenceSecondsLeft({4.0, 3.0, 2.0, 1.0}, 3), 0.0);   // a line below zero counts nothing
    EXPECT_DOUBLE_EQ(sequenceSecondsLeft({1.0, 2.0, 3.0}, 0), 0.0);
}

// Without a terminal, --progress lines name the stage running (a long march), count the time left
// down between frames, and end with a line that says the sequence is done.
TEST(Sequence, ProgressLinesNameTheRunningStageAndEnd) {
    const std::string dir = cloudFrames("progress_lines");
    const CliResult r = runCli("render " + dir + "/cloud.####.vdb --frames 1-2 --res 320x320 --backend cpu --method reference --spp 16 -o " +
                               dir + "/out.####.exr --progress=0.2");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("  frame 1: march"), std::string::npos) << r.err;
    const std::string lines = linesStartingWith(r.err, "voxlux: progress: ");
    const std::string last = lines.substr(lines.rfind("voxlux: progress: "));
    EXPECT_EQ(last.rfind("voxlux: progress: [====================] sequence 2/2 frames  elapsed ", 0), 0u) << last;
    EXPECT_EQ(last.substr(last.size() - 7), "  done\n") << last;
}

// Every second frame, and a list: only those frames render.
TEST(Sequence, StepsAndListsRenderTheirFramesOnly) {
    const std::string dir = cloudFrames("frame_lists");
    CliResult r = runCli(renderArgs(dir, "1-4x2"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir + "/out.0001.exr") && fs::exists(dir + "/out.0003.exr"));
    EXPECT_FALSE(fs::exists(dir + "/out.0002.exr") || fs::exists(dir + "/out.0004.exr"));
    r = runCli(renderArgs(dir, "2,4"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(countOf(r.out, "wrote "), 2u);
    EXPECT_TRUE(fs::exists(dir + "/out.0004.exr"));
    r = runCli(renderArgs(dir, "4,2"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --frames 4,2: /volumes/0/frames: frames must increase: 2 follows 4\n");
}

// On a terminal the bar names the frame and the stage running (script(1) gives the render one).
TEST(Sequence, TheProgressBarShowsTheFrameAndStage) {
    const std::string dir = cloudFrames("progress_bar");
    CliResult r = runShell("script -qec '" + voxluxBinary() + " " + renderArgs(dir, "1-2") + "' /dev/null");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const size_t bar = r.out.find("] sequence 0/2 frames  elapsed ");
    ASSERT_NE(bar, std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  frame 1: march", bar), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("] sequence 1/2 frames  elapsed "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frame 2: march"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace voxlux::test
