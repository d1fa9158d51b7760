// `voxlux view` in a window, on a virtual X display (xvfb-run, Mesa): scripted actions and their
// screenshots, real X events sent with xdotool, errors that keep the viewer running, and no display.
#include <gtest/gtest.h>

#include <png.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "core/json_reader.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

const std::string kXvfb = "xvfb-run -a -s '-screen 0 1600x900x24' ";
const std::string kCloud = sourceDir() + "/grids/default.json --res 160x100 --filter trilinear";

// Writes {"actions": actions} to `dir`/`name` and returns its path.
std::string writeScript(const std::string& dir, const std::string& name, const nlohmann::json& actions) {
    const std::string path = dir + "/" + name;
    std::ofstream(path) << nlohmann::json({{"actions", actions}}).dump(1);
    return path;
}

CliResult view(const std::string& args) { return runShell(kXvfb + voxluxBinary() + " view " + args); }

// Runs the shell script `shell` on the virtual display, with each key of `words` in it replaced,
// then DIR (which the words may hold): the viewer in the background and xdotool's events beside it.
CliResult runEvents(const std::string& dir, std::string shell, const std::map<std::string, std::string>& words) {
    const auto replace = [&shell](const std::string& from, const std::string& to) {
        for (size_t at = shell.find(from); at != std::string::npos; at = shell.find(from, at + to.size())) shell.replace(at, from.size(), to);
    };
    for (const auto& [from, to] : words) replace(from, to);
    replace("DIR", dir);
    std::ofstream(dir + "/events.sh") << shell << "\n";
    return runShell(kXvfb + "bash " + dir + "/events.sh");
}

// Frames 1..`frames` of a box growing `growth` voxels a frame (box_0001.vdb, ...), and boxes.json
// rendering them at 160x100 on the CPU.
void writeBoxSequence(const std::string& dir, int frames, int growth) {
    for (int f = 1; f <= frames; ++f)
        openvdb::io::File(dir + "/box_000" + std::to_string(f) + ".vdb").write({boxGrid({0, 0, 0}, {growth * f, 15, 15}, 2.0f, 0.1)});
    std::ofstream(dir + "/boxes.json") << R"({"volume": {"path": "box_####.vdb", "frames": [1, )" << frames << R"(]},
        "lights": [{"type": "directional", "direction": [-1, -1, 0], "intensity": 2}],
        "render": {"resolution": [160, 100], "backend": "cpu"}})";
}

nlohmann::json readJson(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

struct Rgb {
    int width = 0, height = 0;
    std::vector<uint8_t> bytes;
};
Rgb readPng(const std::string& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    Rgb out;
    if (!png_image_begin_read_from_file(&image, path.c_str())) return out;
    image.format = PNG_FORMAT_RGB;
    out.bytes.resize(PNG_IMAGE_SIZE(image));
    png_image_finish_read(&image, nullptr, out.bytes.data(), 0, nullptr);
    out.width = int(image.width);
    out.height = int(image.height);
    return out;
}

// Mean of the 8-bit values in columns [x0, x1) of the image.
double columnsMean(const Rgb& img, int x0, int x1) {
    double sum = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c) sum += img.bytes[(size_t(y) * img.width + x) * 3 + c];
    return sum / (3.0 * img.height * (x1 - x0));
}

TEST(ViewerWindow, TheConvergedViewportIsVoxluxRenderOfTheSavedScene) {
    const std::string dir = tempDir("viewer-roundtrip");
    const std::string script = writeScript(dir, "s.json", {{{"orbit", {25, -10}}}, {{"set", "material.anisotropy=0.5"}},
                                                           {{"screenshot", dir + "/view.png"}}, {{"save", dir + "/saved.json"}},
                                                           {{"set", "output.path=\"" + dir + "/viewer.exr\""}}, {{"render", true}},
                                                           {{"stats", dir + "/stats.json"}}, {{"quit", true}}});
    const CliResult r = view(kCloud + " --script " + script);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const CliResult render = runCli("render " + dir + "/saved.json -o " + dir + "/r.exr --preview " + dir + "/r.png");
    ASSERT_EQ(render.exit_code, 0) << render.err;
    const Rgb shown = readPng(dir + "/view.png"), rendered = readPng(dir + "/r.png");
    ASSERT_EQ(shown.width, 160);
    EXPECT_EQ(shown.bytes, rendered.bytes);
    // The viewer's Render writes, through the same code, the EXR `voxlux render` writes.
    EXPECT_EQ(readJson(dir + "/stats.json")["message"], "wrote " + dir + "/viewer.exr");
    const Exr a = readExr(dir + "/viewer.exr"), b = readExr(dir + "/r.exr");
    EXPECT_EQ(a.planes, b.planes);
    EXPECT_FLOAT_EQ(readJson(dir + "/saved.json")["volumes"][0]["material"]["anisotropy"].get<float>(), 0.5f);
}

TEST(ViewerWindow, MirroringTheSunMovesTheLitSide) {
    const std::string dir = tempDir("viewer-lit-side");
    const std::string script = writeScript(dir, "s.json", {{{"screenshot", dir + "/left.png"}},
                                                           {{"light", "sun"}, {"set", {{"direction", {-0.65, -0.6, -0.45}}}}},
                                                           {{"screenshot", dir + "/right.png"}}, {{"quit", true}}});
    const CliResult r = view(kCloud + " --script " + script);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Rgb before = readPng(dir + "/left.png"), after = readPng(dir + "/right.png");
    ASSERT_EQ(before.width, 160);
    // The sun travels towards +x first, so it lights the cloud's left; mirrored, its right. The
    // cloud is not symmetric, so the test compares the right-to-left ratios of the two images.
    const double right_before = columnsMean(before, 80, 120) / columnsMean(before, 40, 80);
    const double right_after = columnsMean(after, 80, 120) / columnsMean(after, 40, 80);
    EXPECT_LT(right_before, 0.9);
    EXPECT_GT(right_after, 1.15 * right_before);
}

TEST(ViewerWindow, ALightOffAndOnAgainGivesTheSameImage) {
    const std::string dir = tempDir("viewer-toggle");
    const std::string script = writeScript(dir, "s.json", {{{"screenshot", dir + "/a.png"}}, {{"enable", "sun"}, {"on", false}},
                                                           {{"screenshot", dir + "/off.png"}}, {{"enable", "sun"}, {"on", true}},
                                                           {{"screenshot", dir + "/b.png"}}, {{"stats", dir + "/stats.json"}},
                                                           {{"quit", true}}});
    const CliResult r = view(kCloud + " --script " + script);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(readPng(dir + "/a.png").bytes, readPng(dir + "/b.png").bytes);
    EXPECT_NE(readPng(dir + "/a.png").bytes, readPng(dir + "/off.png").bytes);
    // The sky's median-cut lights stay in the illumination volume: off, the sun is taken out of
    // it, and on again put back in, each a selective update of the sun alone.
    const nlohmann::json stats = readJson(dir + "/stats.json");
    EXPECT_EQ(stats["entire_updates"], 1);
    EXPECT_EQ(stats["selective_updates"], 2);
}

TEST(ViewerWindow, BadEditsAndMissingFilesShowTheErrorAndTheViewerGoesOn) {
    const std::string dir = tempDir("viewer-errors");
    const std::string missing = dir + "/gone.vdb";
    const std::string script = writeScript(dir, "s.json", {{{"screenshot", dir + "/a.png"}},
                                                           {{"set", "material.albedo=[2,0]"}},
                                                           {{"stats", dir + "/bad-edit.json"}},
                                                           {{"set", "volume.path=" + missing}},
                                                           {{"wait", "converged"}},
                                                           {{"stats", dir + "/missing.json"}},
                                                           {{"screenshot", dir + "/b.png"}}, {{"save", dir + "/saved.json"}},
                                                           {{"quit", true}}});
    const CliResult r = view(kCloud + " --script " + script);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string refused = "set material.albedo=[2,0]: /volumes/0/material/albedo: expected an array of 3 numbers";
    EXPECT_EQ(r.err, "voxlux: warning: " + script + ": /actions/1: " + refused + "\n");
    EXPECT_EQ(readJson(dir + "/bad-edit.json")["message"], refused);
    EXPECT_EQ(readJson(dir + "/missing.json")["message"], missing + ": no such file");
    // The last good state, shown again and saved.
    EXPECT_EQ(readPng(dir + "/a.png").bytes, readPng(dir + "/b.png").bytes);
    const std::string saved_volume = readJson(dir + "/saved.json")["volumes"][0]["path"];
    EXPECT_EQ(std::filesystem::canonical(dir + "/" + saved_volume), std::filesystem::canonical(sourceDir() + "/grids/cloud.vdb"));
}

TEST(ViewerWindow, WithoutADisplayItSaysSoAndExitsWith2) {
    const CliResult r = runShell("env -u DISPLAY " + voxluxBinary() + " view " + kCloud);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: voxlux view: no display (DISPLAY is not set); run it on a desktop, or under xvfb-run for scripts\n");
}

TEST(ViewerWindow, RealXEventsOrbitTheCameraAndUncheckALight) {
    const std::string dir = tempDir("viewer-xdotool");
    std::filesystem::remove(dir + "/layout.json");
    std::filesystem::remove(dir + "/go.flag");
    const std::string script = writeScript(dir, "s.json", {{{"wait", "converged"}}, {{"layout", dir + "/layout.json"}},
                                                           {{"wait_file", dir + "/go.flag"}, {"timeout", 120}},
                                                           {{"wait", 0.5}}, {{"save", dir + "/saved.json"}}, {{"quit", true}}});
    // The viewer in the background; once it has written its layout, xdotool clicks the first
    // light's enable box and Alt-drags across the image, then lets the script go on.
    const std::string events = R"sh(
        box=$(python3 -c "import json; r = json.load(open('DIR/layout.json'))['widgets']['light/0/enable']; print(int((r[0]+r[2])/2), int((r[1]+r[3])/2))")
        img=$(python3 -c "import json; r = json.load(open('DIR/layout.json'))['image']; print(int((r[0]+r[2])/2), int((r[1]+r[3])/2))")
        set -- $box; bx=$1; by=$2; set -- $img; ix=$1; iy=$2
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        xdotool mousemove --window $wid $bx $by; sleep 0.3; xdotool click 1; sleep 0.3
        xdotool mousemove --window $wid $ix $iy; sleep 0.3
        xdotool keydown Alt_L mousedown 1; sleep 0.2
        for i in $(seq 10); do xdotool mousemove_relative 8 0; sleep 0.05; done
        xdotool mouseup 1 keyup Alt_L; sleep 0.3
        touch DIR/go.flag)sh";
    const CliResult r = runEvents(dir, "VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done;" +
                                           events + "; wait $pid",
                                  {{"VIEWER", voxluxBinary() + " view " + kCloud}, {"SCRIPT", script}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json saved = readJson(dir + "/saved.json");
    EXPECT_EQ(saved["lights"][0]["enabled"], false);
    // Dragged to the right, the camera orbits about the cloud: it moves off its start, at the same distance.
    const glm::vec3 start(0.25f, 0.28f, 3.7f), look(0.0f, -0.02f, 0.0f);
    const glm::vec3 now(saved["camera"]["position"][0].get<float>(), saved["camera"]["position"][1].get<float>(),
                        saved["camera"]["position"][2].get<float>());
    EXPECT_GT(glm::length(now - start), 0.3f);
    EXPECT_NEAR(glm::length(now - look), glm::length(start - look), 1e-3f);
}

// A click at the right end of the timeline's slider shows the last frame: the render is asked for
// it (the frame is the viewer's, not a scene key, so it must submit on its own).
TEST(ViewerWindow, AClickOnTheTimelineRendersThatFrame) {
    const std::string dir = tempDir("viewer-timeline");
    for (const char* f : {"layout.json", "go.flag", "stats.json"}) std::filesystem::remove(dir + "/" + f);
    writeBoxSequence(dir, 3, 8);
    const std::string script = writeScript(dir, "s.json", {{{"wait", "converged"}}, {{"layout", dir + "/layout.json"}},
                                                           {{"wait_file", dir + "/go.flag"}, {"timeout", 120}},
                                                           {{"wait", "converged"}}, {{"stats", dir + "/stats.json"}}, {{"quit", true}}});
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        at=$(python3 -c "import json; r = json.load(open('DIR/layout.json'))['widgets']['timeline/frame']; print(int(r[2]) - 3, int((r[1]+r[3])/2))")
        set -- $at
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        xdotool mousemove --window $wid $1 $2; sleep 0.3; xdotool click 1; sleep 0.3
        touch DIR/go.flag; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + dir + "/boxes.json"}, {"SCRIPT", script}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json stats = readJson(dir + "/stats.json");
    EXPECT_EQ(stats["shown_frame"], 3);
    EXPECT_EQ(stats["submitted"], 2);
    EXPECT_EQ(stats["message"], "");
}

// A python3 line that prints the centre of widget NAME from the layout file: "x y".
std::string centreOf(const std::string& name) {
    return "$(python3 -c \"import json; r = json.load(open('DIR/layout.json'))['widgets']['" + name +
           "']; print(int((r[0]+r[2])/2), int((r[1]+r[3])/2))\")";
}

glm::vec3 vec3Of(const nlohmann::json& j) { return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()}; }

// Plain drags navigate as in Houdini's and Blender's viewports: a left drag orbits, a middle drag
// pans, the wheel dollies. A light dragged by its handle is one undo step: Ctrl+Z puts it back
// and leaves the camera where navigation put it, Ctrl+Shift+Z does it again.
TEST(ViewerWindow, PlainDragsNavigateAndALightDragIsOneUndoStep) {
    const std::string dir = tempDir("viewer-navigate");
    for (const char* f : {"layout.json", "orbited.json", "go1", "go2", "go3", "go4"}) std::filesystem::remove(dir + "/" + f);
    nlohmann::json actions = {{{"wait", "converged"}}, {{"save", dir + "/s0.json"}}, {{"layout", dir + "/layout.json"}}};
    for (int k = 1; k <= 4; ++k) {
        actions.push_back({{"wait_file", dir + "/go" + std::to_string(k)}, {"timeout", 120}});
        actions.push_back({{"wait", 0.3}});
        actions.push_back({{"save", dir + "/s" + std::to_string(k) + ".json"}});
        if (k == 1) actions.push_back({{"layout", dir + "/orbited.json"}});   // where the handle is now
    }
    actions.push_back({{"quit", true}});
    const std::string script = writeScript(dir, "s.json", actions);
    std::string orbitedHandle = centreOf("light/0/handle");
    orbitedHandle.replace(orbitedHandle.find("layout.json"), 11, "orbited.json");
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        set -- IMAGE; xdotool mousemove --window $wid $1 $2; sleep 0.3
        xdotool mousedown 1; sleep 0.2; for i in $(seq 10); do xdotool mousemove_relative 8 0; sleep 0.05; done; xdotool mouseup 1; sleep 0.3
        touch DIR/go1; for i in $(seq 100); do [ -f DIR/orbited.json ] && break; sleep 0.1; done; sleep 0.3
        set -- HANDLE; xdotool mousemove --window $wid $1 $2; sleep 0.3
        xdotool mousedown 1; sleep 0.2; for i in $(seq 8); do xdotool mousemove_relative 5 3; sleep 0.05; done; xdotool mouseup 1; sleep 0.3
        touch DIR/go2; sleep 1
        xdotool key ctrl+z; sleep 0.3; touch DIR/go3; sleep 1
        xdotool key ctrl+shift+z; sleep 0.3; touch DIR/go4; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + kCloud}, {"SCRIPT", script},
                                   {"IMAGE", centreOf("image")}, {"HANDLE", orbitedHandle}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    std::vector<nlohmann::json> s;
    for (int k = 0; k <= 4; ++k) s.push_back(readJson(dir + "/s" + std::to_string(k) + ".json"));
    // The plain left drag orbited: the camera moved, at the same distance from what it looks at.
    const glm::vec3 look = vec3Of(s[1]["camera"]["look_at"]);
    EXPECT_GT(glm::length(vec3Of(s[1]["camera"]["position"]) - vec3Of(s[0]["camera"]["position"])), 0.3f);
    EXPECT_NEAR(glm::length(vec3Of(s[1]["camera"]["position"]) - look), glm::length(vec3Of(s[0]["camera"]["position"]) - look), 1e-3f);
    EXPECT_EQ(s[1]["lights"], s[0]["lights"]);
    // The handle drag turned the sun; one Ctrl+Z turned it back whole, the camera stayed; redo again.
    EXPECT_NE(s[2]["lights"][0]["direction"], s[1]["lights"][0]["direction"]);
    EXPECT_EQ(s[3]["lights"], s[1]["lights"]);
    EXPECT_EQ(s[3]["camera"], s[2]["camera"]);
    EXPECT_EQ(s[4]["lights"], s[2]["lights"]);
}

// A Shift + right drag of 80 pixels across the image turns the default scene's sky 32 degrees about
// its up (0.4 degrees a pixel, as a gizmo turns), with no camera move, and re-runs neither the
// load nor the bricks.
TEST(ViewerWindow, AShiftRightDragTurnsTheEnvironmentMap) {
    const std::string dir = tempDir("viewer-environment");
    for (const char* f : {"layout.json", "go"}) std::filesystem::remove(dir + "/" + f);
    const std::string script = writeScript(dir, "s.json", {{{"wait", "converged"}}, {{"save", dir + "/before.json"}},
                                                           {{"layout", dir + "/layout.json"}},
                                                           {{"wait_file", dir + "/go"}, {"timeout", 120}}, {{"wait", "converged"}},
                                                           {{"save", dir + "/turned.json"}}, {{"stats", dir + "/stats.json"}},
                                                           {{"quit", true}}});
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        set -- IMAGE; xdotool mousemove --window $wid $1 $2; sleep 0.3
        xdotool keydown shift; xdotool mousedown 3; sleep 0.2; for i in $(seq 10); do xdotool mousemove_relative 8 0; sleep 0.05; done
        xdotool mouseup 3; xdotool keyup shift; sleep 0.3
        touch DIR/go; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + kCloud}, {"SCRIPT", script}, {"IMAGE", centreOf("image")}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json before = readJson(dir + "/before.json"), turned = readJson(dir + "/turned.json");
    EXPECT_NEAR(turned["lights"][1]["rotation"].get<double>(), 32.0, 3.0) << turned["lights"][1];
    EXPECT_EQ(turned["camera"], before["camera"]);
    EXPECT_EQ(turned["lights"][0], before["lights"][0]);
    const nlohmann::json stats = readJson(dir + "/stats.json");
    ASSERT_TRUE(stats.contains("edit_stages")) << stats;
    for (const auto& stage : stats["edit_stages"]) EXPECT_TRUE(stage != "load" && stage != "brick") << stats;
}

// Quick key taps are never lost, however slowly the UI draws: a path typed into the Render panel's
// output field with a BackSpace in it comes out as typed. A 60-pixel drag of a light's exposure
// moves it 0.6 stops (it moved 5), and the layout of a script names the widgets.
TEST(ViewerWindow, TypedPathsKeepEveryKeyAndTheExposureDragIsFine) {
    const std::string dir = tempDir("viewer-typing");
    for (const char* f : {"layout.json", "typed.json", "go1", "go2"}) std::filesystem::remove(dir + "/" + f);
    // "converged" waits for the keys typed to be handled too.
    const std::string script = writeScript(dir, "s.json", {{{"wait", "converged"}}, {{"save", dir + "/before.json"}},
                                                           {{"layout", dir + "/layout.json"}},
                                                           {{"wait_file", dir + "/go1"}, {"timeout", 120}}, {{"wait", "converged"}},
                                                           {{"save", dir + "/typed.json"}},
                                                           {{"wait_file", dir + "/go2"}, {"timeout", 120}},
                                                           {{"wait", 0.3}}, {{"save", dir + "/after.json"}}, {{"quit", true}}});
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        set -- OUTPUT; xdotool mousemove --window $wid $1 $2; sleep 0.3; xdotool click 1; sleep 0.3
        xdotool key ctrl+a BackSpace; xdotool type --delay 2 "DIR/abc"; xdotool key --delay 2 BackSpace; xdotool type --delay 2 "d.exr"
        xdotool key Return; sleep 0.3; touch DIR/go1
        for i in $(seq 600); do [ -f DIR/typed.json ] && break; sleep 0.1; done
        set -- EXPOSURE; xdotool mousemove --window $wid $1 $2; sleep 0.3
        xdotool mousedown 1; sleep 0.2; for i in $(seq 12); do xdotool mousemove_relative 5 0; sleep 0.05; done; xdotool mouseup 1; sleep 0.3
        touch DIR/go2; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + kCloud}, {"SCRIPT", script},
                                   {"OUTPUT", centreOf("output")}, {"EXPOSURE", centreOf("light/exposure")}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json before = readJson(dir + "/before.json"), after = readJson(dir + "/after.json");
    EXPECT_EQ(readJson(dir + "/typed.json")["output"]["path"], dir + "/abd.exr");
    const double stops = std::log2(after["lights"][0]["intensity"].get<double>() / before["lights"][0]["intensity"].get<double>());
    EXPECT_GT(stops, 0.3);
    EXPECT_LT(stops, 0.9);
}

// The Volumes panel places a volume: a 60-pixel drag of the rotate field's middle (Y) turns it
// 30 degrees about Y, and the edit re-runs the lighting and the march but neither loads nor
// re-bricks the cache.
TEST(ViewerWindow, TheVolumesPanelTurnsAVolumeWithoutReloadingIt) {
    const std::string dir = tempDir("viewer-volumes");
    for (const char* f : {"layout.json", "go"}) std::filesystem::remove(dir + "/" + f);
    const std::string script = writeScript(dir, "s.json", {{{"wait", "converged"}}, {{"layout", dir + "/layout.json"}},
                                                           {{"wait_file", dir + "/go"}, {"timeout", 120}}, {{"wait", "converged"}},
                                                           {{"save", dir + "/turned.json"}}, {{"stats", dir + "/stats.json"}},
                                                           {{"quit", true}}});
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        set -- ROTATE; xdotool mousemove --window $wid $1 $2; sleep 0.3
        xdotool mousedown 1; sleep 0.2; for i in $(seq 12); do xdotool mousemove_relative 5 0; sleep 0.05; done; xdotool mouseup 1; sleep 0.3
        touch DIR/go; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + kCloud}, {"SCRIPT", script}, {"ROTATE", centreOf("volume/0/rotate")}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json transform = readJson(dir + "/turned.json")["volumes"][0]["transform"];
    EXPECT_NEAR(transform["rotate"][1].get<double>(), 30.0, 3.0) << transform;
    EXPECT_EQ(transform["rotate"][0], 0.0);
    EXPECT_EQ(transform["translate"], nlohmann::json({0.0, 0.0, 0.0}));
    const nlohmann::json stats = readJson(dir + "/stats.json");
    ASSERT_TRUE(stats.contains("edit_stages")) << stats;
    for (const auto& stage : stats["edit_stages"]) EXPECT_TRUE(stage != "load" && stage != "brick" && stage != "classify") << stats;
    EXPECT_NE(std::find(stats["edit_stages"].begin(), stats["edit_stages"].end(), "march"), stats["edit_stages"].end()) << stats;
}

// Two clouds side by side. A real 40-pixel drag of the right one's gizmo handle moves it with the
// pointer (the handle lands 40 pixels on) and re-runs neither the load, the brick nor the volumes
// stage; scripted drags turn it 0.4 degrees and scale it 1% a pixel; a click on its checkbox
// disables it.
TEST(ViewerWindow, AVolumesGizmoMovesTurnsAndScalesItAndItsCheckboxHidesIt) {
    const std::string dir = tempDir("viewer-gizmo");
    for (const char* f : {"layout.json", "moved.json", "go1", "go2"}) std::filesystem::remove(dir + "/" + f);
    const nlohmann::json cloud = {{"path", sourceDir() + "/grids/cloud.vdb"}, {"material", {{"density_scale", 40.0}}}};
    nlohmann::json right = cloud;
    right["name"] = "right";
    right["transform"] = {{"translate", {1.0, 0.0, 0.0}}};
    nlohmann::json left = cloud;
    left["name"] = "left";
    std::ofstream(dir + "/two.json") << nlohmann::json{
        {"volumes", {left, right}},
        {"lights", {{{"type", "directional"}, {"direction", {0.65, -0.6, -0.45}}, {"intensity", 8.0}}}},
        {"camera", {{"position", {0.5, 0.0, 5.0}}, {"look_at", {0.5, 0.0, 0.0}}, {"fov", 35.0}}},
        {"render", {{"resolution", {160, 100}}, {"filter", "trilinear"}, {"backend", "cpu"}}},
        {"effects", {{"shadows", "propagation"}}}};
    const std::string script = writeScript(dir, "s.json",
        {{{"wait", "converged"}}, {{"layout", dir + "/layout.json"}}, {{"wait_file", dir + "/go1"}, {"timeout", 120}},
         {{"wait", "converged"}}, {{"layout", dir + "/moved.json"}}, {{"save", dir + "/moved_scene.json"}}, {{"stats", dir + "/stats.json"}},
         {{"drag_volume", "right"}, {"by", {50, 0}}, {"mode", "rotate"}}, {{"save", dir + "/turned.json"}},
         {{"drag_volume", 1}, {"by", {30, 0}}, {"mode", "scale"}}, {{"save", dir + "/scaled.json"}},
         {{"wait_file", dir + "/go2"}, {"timeout", 120}}, {{"wait", 0.3}}, {{"save", dir + "/hidden.json"}}, {{"quit", true}}});
    std::string moved_handle = centreOf("volume/1/handle");
    moved_handle.replace(moved_handle.find("layout.json"), 11, "moved.json");
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        set -- HANDLE; xdotool mousemove --window $wid $1 $2; sleep 0.3
        xdotool mousedown 1; sleep 0.2; for i in $(seq 8); do xdotool mousemove_relative 5 0; sleep 0.05; done; xdotool mouseup 1; sleep 0.3
        touch DIR/go1; for i in $(seq 1200); do [ -f DIR/moved.json ] && break; sleep 0.1; done; sleep 0.3
        set -- ENABLE; xdotool mousemove --window $wid $1 $2; sleep 0.3; xdotool click 1; sleep 0.3
        touch DIR/go2; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + dir + "/two.json"}, {"SCRIPT", script},
                                   {"HANDLE", centreOf("volume/1/handle")}, {"ENABLE", centreOf("volume/1/enable")}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const auto handle = [](const nlohmann::json& layout) {
        const nlohmann::json& w = layout["widgets"]["volume/1/handle"];
        return glm::vec2(w[0].get<float>() + w[2].get<float>(), w[1].get<float>() + w[3].get<float>()) * 0.5f;
    };
    const glm::vec2 travel = handle(readJson(dir + "/moved.json")) - handle(readJson(dir + "/layout.json"));
    EXPECT_NEAR(travel.x, 40.0f, 4.0f);
    EXPECT_NEAR(travel.y, 0.0f, 2.0f);
    const nlohmann::json moved = readJson(dir + "/moved_scene.json")["volumes"][1]["transform"];
    EXPECT_GT(moved["translate"][0].get<double>(), 1.1) << moved;
    EXPECT_EQ(readJson(dir + "/moved_scene.json")["volumes"][0].value("transform", nlohmann::json()), nlohmann::json()) << "the left one stays";
    const nlohmann::json stats = readJson(dir + "/stats.json");
    ASSERT_TRUE(stats.contains("edit_stages")) << stats;
    for (const auto& stage : stats["edit_stages"])
        EXPECT_TRUE(stage != "load" && stage != "brick" && stage != "classify" && stage != "volumes") << stats;
    EXPECT_NE(std::find(stats["edit_stages"].begin(), stats["edit_stages"].end(), "march"), stats["edit_stages"].end()) << stats;
    // The camera looks along -z: a drag across the screen turns about y.
    const nlohmann::json turned = readJson(dir + "/turned.json")["volumes"][1]["transform"];
    EXPECT_NEAR(turned["rotate"][1].get<double>(), 20.0, 0.5) << turned;
    EXPECT_NEAR(turned["rotate"][0].get<double>(), 0.0, 0.5) << turned;
    const nlohmann::json scaled = readJson(dir + "/scaled.json")["volumes"][1]["transform"];
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(scaled["scale"][a].get<double>(), std::exp(0.3), 1e-4) << scaled;
    EXPECT_EQ(readJson(dir + "/hidden.json")["volumes"][1].value("enabled", true), false);
}

// The timeline takes a typed frame (Enter shows it) and the arrow keys step it.
TEST(ViewerWindow, TheTimelineTakesATypedFrameAndTheArrowKeys) {
    const std::string dir = tempDir("viewer-timeline-keys");
    for (const char* f : {"layout.json", "go1", "go2"}) std::filesystem::remove(dir + "/" + f);
    writeBoxSequence(dir, 4, 6);
    const std::string script = writeScript(dir, "s.json", {{{"wait", "converged"}}, {{"layout", dir + "/layout.json"}},
                                                           {{"wait_file", dir + "/go1"}, {"timeout", 120}}, {{"wait", "converged"}},
                                                           {{"stats", dir + "/typed.json"}},
                                                           {{"wait_file", dir + "/go2"}, {"timeout", 120}}, {{"wait", "converged"}},
                                                           {{"stats", dir + "/stepped.json"}}, {{"quit", true}}});
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        set -- TYPED; xdotool mousemove --window $wid $1 $2; sleep 0.3; xdotool click 1; sleep 0.3
        xdotool key ctrl+a BackSpace; xdotool type --delay 2 "3"; xdotool key Return; sleep 0.5
        touch DIR/go1; sleep 1
        set -- IMAGE; xdotool mousemove --window $wid $1 $2; sleep 0.2
        xdotool key Right; sleep 0.3; xdotool key Left; sleep 0.3; xdotool key Left; sleep 0.5
        touch DIR/go2; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + dir + "/boxes.json"}, {"SCRIPT", script},
                                   {"TYPED", centreOf("timeline/typed")}, {"IMAGE", centreOf("image")}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_EQ(readJson(dir + "/typed.json")["shown_frame"], 3);
    EXPECT_EQ(readJson(dir + "/stepped.json")["shown_frame"], 2);
}

// Ctrl + drag over the image draws a render region: the render marches only it (its image is
// empty outside), and Ctrl + click clears it, so the whole image renders again.
TEST(ViewerWindow, ACtrlDragRendersARegionAndACtrlClickClearsIt) {
    const std::string dir = tempDir("viewer-region");
    for (const char* f : {"layout.json", "go1", "go2"}) std::filesystem::remove(dir + "/" + f);
    const std::string script = writeScript(dir, "s.json", {{{"wait", "converged"}}, {{"layout", dir + "/layout.json"}},
                                                           {{"wait_file", dir + "/go1"}, {"timeout", 120}}, {{"wait", "converged"}},
                                                           {{"stats", dir + "/region.json"}}, {{"screenshot", dir + "/region.png"}},
                                                           {{"wait_file", dir + "/go2"}, {"timeout", 120}}, {{"wait", "converged"}},
                                                           {{"stats", dir + "/whole.json"}}, {{"screenshot", dir + "/whole.png"}},
                                                           {{"quit", true}}});
    const CliResult r = runEvents(dir, R"sh(VIEWER --script SCRIPT & pid=$!; for i in $(seq 1200); do [ -f DIR/layout.json ] && break; sleep 0.1; done
        wid=$(xdotool search --sync --onlyvisible --name "voxlux view" | head -1)
        set -- $(python3 -c "import json; r = json.load(open('DIR/layout.json'))['widgets']['image']; print(int(r[0] + 0.3 * (r[2] - r[0])), int(r[1] + 0.3 * (r[3] - r[1])), int(0.4 * (r[2] - r[0]) / 10), int(0.4 * (r[3] - r[1]) / 10))")
        xdotool mousemove --window $wid $1 $2; sleep 0.3
        xdotool keydown ctrl mousedown 1; sleep 0.2; for i in $(seq 10); do xdotool mousemove_relative $3 $4; sleep 0.05; done
        xdotool mouseup 1 keyup ctrl; sleep 0.5; touch DIR/go1
        for i in $(seq 600); do [ -f DIR/region.png ] && break; sleep 0.1; done; sleep 0.3
        xdotool keydown ctrl click 1; xdotool keyup ctrl; sleep 0.5; touch DIR/go2; wait $pid)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + kCloud}, {"SCRIPT", script}});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json region = readJson(dir + "/region.json")["region"];
    ASSERT_EQ(region.size(), 4u) << readJson(dir + "/region.json").dump();
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(region[k].get<double>(), k < 2 ? 0.3 : 0.7, 0.03) << k;
    EXPECT_FALSE(readJson(dir + "/whole.json").contains("region"));
    // The region's image is empty (black) outside it; the whole image has the cloud there.
    const Rgb inside = readPng(dir + "/region.png"), whole = readPng(dir + "/whole.png");
    ASSERT_EQ(inside.width, 160);
    EXPECT_EQ(columnsMean(inside, 0, 40), 0.0);
    EXPECT_GT(columnsMean(whole, 0, 40), 1.0);   // the cloud reaches in there
    EXPECT_GT(columnsMean(inside, 56, 104), 5.0);
}

// Idle, with the image converged and nothing changing, the viewer sleeps: at most 1% of a core.
TEST(ViewerWindow, IdleTakesUnderOnePercentOfACore) {
    const std::string dir = tempDir("viewer-idle");
    std::filesystem::remove(dir + "/cpu.txt");
    std::filesystem::remove(dir + "/rc.txt");
    // CPU seconds of the viewer (utime + stime, in clock ticks) once its usage has settled, then 5 s
    // later. The viewer's exit code is written by the script: xvfb-run's own can be 5 when removing
    // its temporary folder races with another test's X server under ctest -j2.
    const CliResult r = runEvents(dir, R"sh(VIEWER & pid=$!
        timeout 120 xdotool search --sync --onlyvisible --name "voxlux view" >/dev/null
        ticks() { awk '{print $14 + $15}' /proc/$pid/stat; }
        last=$(ticks); for i in $(seq 120); do sleep 1; now=$(ticks); [ $((now - last)) -le 2 ] && break; last=$now; done
        start=$(ticks); sleep 5; end=$(ticks)
        echo $((end - start)) $(getconf CLK_TCK) > DIR/cpu.txt; kill -TERM $pid; wait $pid; echo $? > DIR/rc.txt)sh",
                                  {{"VIEWER", voxluxBinary() + " view " + kCloud}});
    int rc = -1;
    std::ifstream(dir + "/rc.txt") >> rc;
    EXPECT_EQ(rc, 143) << r.err << r.out;
    double ticks = -1, per_second = 100;
    std::ifstream(dir + "/cpu.txt") >> ticks >> per_second;
    ASSERT_GE(ticks, 0.0);
    EXPECT_LE(ticks / per_second, 0.05) << ticks << " ticks in 5 s";
}

// One SIGINT or SIGTERM closes the window at once, as the close button does, and the exit code
// says which signal (a script that stops the viewer with one `kill` must not hang).
TEST(ViewerWindow, OneSignalClosesTheWindowWithinTwoSeconds) {
    const std::string dir = tempDir("viewer-signal");
    for (const auto& [signal, code] : {std::pair<std::string, int>{"INT", 130}, {"TERM", 143}}) {
        std::filesystem::remove(dir + "/rc.txt");
        const CliResult r = runEvents(dir, R"sh(VIEWER & pid=$!
            timeout 120 xdotool search --sync --onlyvisible --name "voxlux view" >/dev/null; sleep 1
            kill -SIGNAL $pid; start=$(date +%s%N); wait $pid; rc=$?
            echo $rc $(( ($(date +%s%N) - start) / 1000000 )) > DIR/rc.txt)sh",
                                      {{"VIEWER", voxluxBinary() + " view " + kCloud}, {"SIGNAL", signal}});
        ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
        int rc = -1, ms = -1;
        std::ifstream(dir + "/rc.txt") >> rc >> ms;
        EXPECT_EQ(rc, code) << "SIG" << signal;
        EXPECT_LT(ms, 2000) << "SIG" << signal;
    }
}

}  // namespace
}  // namespace voxlux::test
