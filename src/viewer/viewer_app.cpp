#include "viewer/viewer_app.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <thread>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "core/error.h"
#include "core/json_reader.h"
#include "core/progress.h"
#include "core/thread_limit.h"
#include "core/quantile.h"
#include "io/exr_writer.h"
#include "io/png_writer.h"
#include "render/renderer.h"
#include "viewer/key_trickle.h"
#include "viewer/orbit_camera.h"
#include "viewer/view_script.h"
#include "viewer/viewer_panels.h"
#include "viewer/viewport.h"

namespace voxlux {
namespace {

using Clock = std::chrono::steady_clock;
constexpr float kScenePanelWidth = 380.0f, kImagePanelWidth = 300.0f, kTimelineHeight = 40.0f, kMessageHeight = 22.0f;
constexpr double kConvergeTimeout = 300.0;   // seconds a script waits for one image
constexpr double kFrameRate = 60.0;          // the UI's most frames a second while rendering
constexpr int kSettleFrames = 3;             // frames drawn after an event before the UI sleeps

std::string glfwProblem;
extern "C" void onGlfwError(int, const char* text) { glfwProblem = text; }

// Writes display-referred RGBA8 read back from the window (rows bottom-up) as a PNG.
void writeWindowPng(const std::string& path, int width, int height) {
    std::vector<uint8_t> bytes(size_t(width) * height * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    std::vector<glm::vec4> rgba(size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const uint8_t* p = &bytes[(size_t(height - 1 - y) * width + x) * 4];
            rgba[size_t(y) * width + x] = glm::vec4(p[0], p[1], p[2], 255) / 255.0f;
        }
    writePng(path, width, height, rgba, false);
}

// Renders the scene to its output path on a thread of its own, as `voxlux render` does; Ctrl-C
// or SIGTERM stops it at the next stage, so the window closes at once.
std::future<std::string> renderInBackground(const Scene& scene, std::optional<int> frame) {
    return std::async(std::launch::async, [scene, frame] {
        Renderer renderer(scene);
        renderer.setCancellation([] { return interruptSignal() != 0; });
        const FrameResult r = renderer.renderToFile(frame, frame.has_value());
        return "wrote " + writtenFilesText(r);
    });
}

// "fire-view.json" for "fire_####.vdb": the source's name without its frame pattern.
std::string defaultSaveName(const std::string& source) {
    std::string stem = std::filesystem::path(source).stem().string();
    stem.erase(std::remove(stem.begin(), stem.end(), '#'), stem.end());
    while (!stem.empty() && (stem.back() == '_' || stem.back() == '.' || stem.back() == '-')) stem.pop_back();
    return (stem.empty() ? "scene" : stem) + "-view.json";
}

// The edits `--bench` times: each case applied `kBenchRepeats` times, waiting for convergence.
constexpr int kBenchRepeats = 5;
std::vector<ViewAction> benchActions(const Scene& scene) {
    std::vector<ViewAction> a;
    // The kind is the action's first key as written (a JSON object's keys are kept sorted).
    const auto add = [&a](const std::string& kind, nlohmann::json value, nlohmann::json more = nlohmann::json::object()) {
        more[kind] = std::move(value);
        a.push_back({kind, more, "--bench"});
    };
    add("wait", "converged");
    int key = -1;
    for (size_t i = 0; i < scene.lights.size() && key < 0; ++i)
        if (scene.lights[i].type != LightType::Ambient && scene.lights[i].type != LightType::Environment && scene.lights[i].enabled) key = int(i);
    for (int k = 0; k < kBenchRepeats; ++k) {
        if (key >= 0) {
            add("drag_light", key, {{"by", {k % 2 ? -12 : 12, 0}}});
            add("bench_record", "light edit");   // waits for the converged image first
        }
        add("orbit", {k % 2 ? -5 : 5, 0});
        add("bench_record", "camera orbit");
        add("set", "material.anisotropy=" + std::to_string(k % 2 ? 0.3 : 0.35));
        add("bench_record", "material change");
        add("set", std::string("volume.transform.rotate=[0,") + (k % 2 ? "0" : "2") + ",0]");
        add("bench_record", "volume move");
    }
    add("bench_report", true);
    add("quit", true);
    return a;
}

struct BenchCase {
    std::vector<double> first, converged, slowest_frame;
};

class ViewerApp {
public:
    ViewerApp(const Scene& scene, const ViewerOptions& options, std::vector<ViewAction> script, GLFWwindow* window)
        : options_(options), state_(scene), script_(std::move(script)), keys_(window) {}

    int run(GLFWwindow* window);

private:
    void syncRender();
    bool runScript();                 // false once the script quits
    bool runAction(const ViewAction& a);   // false while it waits
    bool converged() const;
    void shortcuts();
    void drawFrame(GLFWwindow* window);

    ViewerOptions options_;
    ViewerState state_;
    Viewport viewport_;
    EnvironmentThumbnailWidget thumbnail_;
    std::vector<ViewAction> script_;
    KeyTrickle keys_;
    size_t next_ = 0;
    Clock::time_point wait_until_{}, wait_start_{};
    bool waiting_ = false;
    std::string window_png_;           // written after the next frame is drawn
    std::future<std::string> rendering_, script_render_;
    std::map<std::string, BenchCase> bench_;
    std::vector<std::string> bench_order_;
    std::string shown_error_;
    int exit_code_ = 0;
    int settle_frames_ = 0;   // frames still to draw before the loop sleeps
    bool drawn_ = false;      // a frame has been drawn
};

void ViewerApp::syncRender() {
    if (auto f = state_.render->failure(); f && f->edit > state_.failure_seen) {
        state_.failure_seen = f->edit;
        state_.showError(f->message);
        if (f->restored) {   // the worker renders the last good state already: show it as the state
            state_.editor.adopt(f->last_good);
            state_.frame = f->last_good_frame;
            state_.submitted_version = state_.editor.version();
            state_.submitted_frame = state_.frame;
        }
    }
    if (!state_.editor.error().empty() && state_.editor.error() != shown_error_) state_.showError(state_.editor.error());
    shown_error_ = state_.editor.error();
    // The render is asked for the scene and frame shown, unless playback runs through the
    // flipbook: then the frame is submitted once playback stops or reaches a frame not in it.
    if (state_.flipbook_version != state_.editor.version()) state_.emptyFlipbook();
    const bool flipping = state_.playing && state_.frame && state_.flipbook.count(*state_.frame);
    if ((state_.submitted_version != state_.editor.version() || state_.submitted_frame != state_.frame ||
         state_.submitted_region != state_.region) && !flipping) {
        state_.submitted_edit = state_.render->submit(state_.renderedScene(), state_.frame);
        state_.submitted_version = state_.editor.version();
        state_.submitted_frame = state_.frame;
        state_.submitted_region = state_.region;
    }
    if (state_.frame) state_.remember(state_.render->latest());
    // The gizmos' boxes, after a new frame, file or grid; not during playback, where reading every
    // volume's file each frame would hold the UI up for handles no one drags.
    if (!state_.playing) state_.readVolumeBoxes();
    if (rendering_.valid() && rendering_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        try {
            state_.showNote(rendering_.get());
        } catch (const std::exception& e) {
            state_.showError(e.what());
        }
    }
}

// Converged, for a script: the newest edit rendered in full, and every key typed handled.
bool ViewerApp::converged() const {
    return state_.submitted_version == state_.editor.version() && state_.render->settled() && !keys_.pending();
}

bool ViewerApp::runAction(const ViewAction& a) {
    const nlohmann::json& v = a.value[a.kind];
    const auto light = [&] { return state_.editor.lightIndex(v); };
    // An edit the scene refuses is shown as the UI shows it, and the script goes on.
    const auto check = [&](bool took) {
        if (!took) std::cerr << "voxlux: warning: " << a.where << ": " << state_.editor.error() << "\n";
    };
    if (a.kind == "wait" || a.kind == "screenshot" || a.kind == "bench_record") {
        if (!waiting_) wait_start_ = Clock::now(), waiting_ = true;
        if (v.is_number()) {
            if (Clock::now() - wait_start_ < std::chrono::duration<double>(v.get<double>())) return false;
        } else if (!converged()) {
            if (Clock::now() - wait_start_ > std::chrono::duration<double>(kConvergeTimeout))
                throw InputError(a.where + ": no converged image after " + std::to_string(int(kConvergeTimeout)) + " s");
            return false;
        }
        waiting_ = false;
    }
    if (a.kind == "wait_file") {
        if (!waiting_) wait_start_ = Clock::now(), waiting_ = true;
        if (!std::filesystem::exists(v.get<std::string>())) {
            if (Clock::now() - wait_start_ > std::chrono::duration<double>(a.value.value("timeout", 60.0)))
                throw InputError(a.where + ": " + v.get<std::string>() + " did not appear");
            return false;
        }
        waiting_ = false;
    }
    if (a.kind == "set") check(state_.editor.set(v.get<std::string>()));
    if (a.kind == "undo" && !state_.editor.undo()) std::cerr << "voxlux: warning: " << a.where << ": nothing to undo\n";
    if (a.kind == "redo" && !state_.editor.redo()) std::cerr << "voxlux: warning: " << a.where << ": nothing to redo\n";
    if (a.kind == "light") {   // and shows its panel, as a click on it in the list does
        state_.selected_light = light();
        check(state_.editor.changeLight(state_.selected_light, a.value["set"]));
    }
    if (a.kind == "enable") check(state_.editor.enableLight(light(), a.value["on"].get<bool>()));
    if (a.kind == "solo") check(state_.editor.soloLight(light()));
    if (a.kind == "solo_group") check(state_.editor.soloGroup(v.get<std::string>()));
    if (a.kind == "remove_light") check(state_.editor.removeLight(light()));
    if (a.kind == "add_light") check(state_.editor.addLight(v));
    if (a.kind == "drag_light") {
        const glm::vec2 size = viewport_.imageHi() - viewport_.imageLo();
        check(Viewport::dragLight(state_, light(), glm::vec2(a.value["by"][0].get<float>(), a.value["by"][1].get<float>()), size));
    }
    if (a.kind == "drag_volume") {
        const int index = state_.editor.volumeIndex(v);
        if (a.value.contains("mode"))
            state_.volume_gizmo = VolumeGizmo(std::find(kVolumeGizmoNames.begin(), kVolumeGizmoNames.end(), a.value["mode"]) - kVolumeGizmoNames.begin());
        state_.selected_volume = index;
        const glm::vec2 size = viewport_.imageHi() - viewport_.imageLo();
        check(Viewport::dragVolume(state_, index, glm::vec2(a.value["by"][0].get<float>(), a.value["by"][1].get<float>()), size));
    }
    if (a.kind == "orbit") check(state_.editor.setCamera(orbit(state_.camera(), v[0].get<float>(), v[1].get<float>())));
    if (a.kind == "pan") check(state_.editor.setCamera(pan(state_.camera(), glm::vec2(v[0].get<float>(), v[1].get<float>()))));
    if (a.kind == "dolly") check(state_.editor.setCamera(dolly(state_.camera(), v.get<float>())));
    if (a.kind == "frame") {
        state_.updateBounds();
        check(state_.editor.setCamera(frameAlong(state_.camera(), state_.bounds_lo, state_.bounds_hi)));
    }
    if (a.kind == "frame_number") {
        if (!state_.frame) throw InputError(a.where + ": the scene is not a sequence");
        state_.showFrame(v.get<int>());
    }
    if (a.kind == "region") {
        if (v.is_boolean()) {
            state_.region.reset();
        } else {
            const std::array<float, 4> b{v[0].get<float>(), v[1].get<float>(), v[2].get<float>(), v[3].get<float>()};
            if (!isRegion(b)) throw InputError(a.where + "/region: " + kRegionExpected);
            state_.backdrop = state_.image();
            state_.region = b;
        }
    }
    if (a.kind == "aov") {
        if (std::find(kViewAovs.begin(), kViewAovs.end(), v.get<std::string>()) == kViewAovs.end())
            throw InputError(a.where + ": no AOV \"" + v.get<std::string>() + "\" (beauty, direct, indirect, ambient, emission, transmittance, depth)");
        state_.aov = v.get<std::string>();
    }
    if (a.kind == "screenshot") {
        const auto f = state_.render->latest();
        if (!f) throw InputError(a.where + ": no image (" + state_.message + ")");
        writePng(v.get<std::string>(), f->image.width, f->image.height, f->display, false);
    }
    if (a.kind == "window_screenshot") window_png_ = v.get<std::string>();
    if (a.kind == "save") {
        state_.editor.save(v.get<std::string>());
        state_.showNote("wrote " + v.get<std::string>());
    }
    if (a.kind == "render") {   // a future of its own: the UI's Render button has rendering_
        if (!script_render_.valid()) script_render_ = renderInBackground(state_.editor.scene(), state_.frame);
        if (script_render_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
        state_.showNote(script_render_.get());   // a failed render throws its one line, and the script stops
    }
    if (a.kind == "stats" || a.kind == "layout") {
        nlohmann::json out;
        if (a.kind == "stats") {
            const ViewStatistics st = state_.render->statistics();
            out = {{"submitted", st.submitted}, {"rendered", st.rendered}, {"converged", st.converged}, {"cancelled", st.cancelled},
                   {"selective_updates", st.selective_updates}, {"entire_updates", st.entire_updates}, {"kept_updates", st.kept_updates},
                   {"first_image_seconds", st.first_image_seconds}, {"converged_seconds", st.converged_seconds},
                   {"ui_fps", state_.ui_fps}, {"message", state_.message}};
            if (state_.region) out["region"] = *state_.region;
            if (const auto f = state_.render->latest()) {
                for (const StageReport& s : f->edit_stages) out[s.cached ? "cached_stages" : "edit_stages"].push_back(s.name);
                out["frame_cache"] = {{"outputs", f->cache_outputs}, {"bytes", f->cache_bytes}, {"budget", state_.frame_cache_bytes}};
                if (f->frame) out["shown_frame"] = *f->frame;
            }
        } else {
            for (const auto& [name, r] : state_.widgets) out["widgets"][name] = {r.x, r.y, r.z, r.w};
            out["image"] = {viewport_.imageLo().x, viewport_.imageLo().y, viewport_.imageHi().x, viewport_.imageHi().y};
        }
        writeFileAtomically(v.get<std::string>(), jsonText(out, 2) + "\n");
    }
    if (a.kind == "bench_record") {
        const ViewStatistics st = state_.render->statistics();
        const std::string name = v.get<std::string>();
        if (!bench_.count(name)) bench_order_.push_back(name);
        bench_[name].first.push_back(st.first_image_seconds);
        bench_[name].converged.push_back(st.converged_seconds);
        bench_[name].slowest_frame.push_back(state_.slowest_ui_frame);
    }
    if (a.kind == "bench_report") {
        const Scene& s = state_.editor.scene();
        std::printf("voxlux view --bench: %s, %dx%d, %s backend, medians of %d edits\n", options_.source.c_str(), s.render.width,
                    s.render.height, s.render.backend == Backend::Gl ? "gl" : "cpu", kBenchRepeats);
        std::printf("%-16s %14s %14s %12s   %s\n", "edit", "first image", "converged", "UI fps (min)", "each edit: first / converged ms");
        for (const auto& name : bench_order_) {
            const BenchCase& c = bench_[name];
            const double slowest = *std::max_element(c.slowest_frame.begin(), c.slowest_frame.end());
            std::printf("%-16s %11.1f ms %11.1f ms %12.0f  ", name.c_str(), quantile(c.first, 0.5) * 1000.0, quantile(c.converged, 0.5) * 1000.0,
                        slowest > 0.0 ? 1.0 / slowest : 0.0);
            for (size_t k = 0; k < c.first.size(); ++k) std::printf(" %.0f/%.0f", c.first[k] * 1000.0, c.converged[k] * 1000.0);
            std::printf("\n");
        }
        std::fflush(stdout);
    }
    // Each edit's slowest UI frame is measured from the edit on, through its wait.
    if (a.kind != "wait" && a.kind != "bench_record") state_.slowest_ui_frame = 0.0;
    return true;
}

bool ViewerApp::runScript() {
    while (next_ < script_.size()) {
        const ViewAction& a = script_[next_];
        syncRender();
        if (!runAction(a)) return true;
        ++next_;
        if (a.kind == "quit") return false;
        if (a.kind != "wait" && a.kind != "wait_file") return true;   // let the UI draw the edit before the next action
    }
    return true;
}

// Keys that act on the whole viewer, unless a text field has the keyboard: Ctrl+Z undoes,
// Ctrl+Shift+Z (or Ctrl+Y) redoes, the left and right arrows step a sequence's frames. A mouse button held down holds the undo step, so a drag is one.
void ViewerApp::shortcuts() {
    const ImGuiIO& io = ImGui::GetIO();
    state_.editor.holdStep(ImGui::IsAnyMouseDown());
    if (io.WantTextInput) return;
    if (state_.frame && !io.KeyCtrl) {   // the arrow keys step through a sequence
        if (ImGui::IsKeyPressed(GLFW_KEY_LEFT)) state_.showFrame(*state_.frame - 1);
        if (ImGui::IsKeyPressed(GLFW_KEY_RIGHT)) state_.showFrame(*state_.frame + 1);
    }
    if (!io.KeyCtrl) return;
    const bool redo = ImGui::IsKeyPressed(GLFW_KEY_Y) || (io.KeyShift && ImGui::IsKeyPressed(GLFW_KEY_Z));
    const bool undo = !io.KeyShift && ImGui::IsKeyPressed(GLFW_KEY_Z);
    if (undo) state_.editor.undo() ? state_.showNote("undone") : state_.showNote("nothing to undo");
    if (redo) state_.editor.redo() ? state_.showNote("redone") : state_.showNote("nothing to redo");
}

void ViewerApp::drawFrame(GLFWwindow* window) {
    int w = 0, h = 0;
    glfwGetWindowSize(window, &w, &h);
    keys_.deliver();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    shortcuts();
    const float bottom = float(h) - kMessageHeight - (state_.frame ? kTimelineHeight : 0.0f);
    const PanelRequests requests = drawScenePanel(state_, thumbnail_, 0.0f, kScenePanelWidth, float(h));
    viewport_.draw(state_, glm::vec2(kScenePanelWidth, 0.0f), glm::vec2(float(w) - kImagePanelWidth, bottom));
    drawImagePanel(state_, viewport_, float(w) - kImagePanelWidth, kImagePanelWidth, float(h));
    drawTimeline(state_, kScenePanelWidth, bottom, float(w) - kScenePanelWidth - kImagePanelWidth);
    ImGui::GetForegroundDrawList()->AddText(ImVec2(kScenePanelWidth + 8.0f, float(h) - kMessageHeight + 3.0f),
                                            state_.message_is_error ? IM_COL32(255, 90, 80, 255) : IM_COL32(200, 200, 200, 255),
                                            state_.message.c_str());
    if (requests.save) {
        try {
            state_.editor.save(state_.save_path);
            state_.showNote("wrote " + state_.save_path);
        } catch (const std::exception& e) {
            state_.showError(e.what());
        }
    }
    if (requests.render && !rendering_.valid()) {
        rendering_ = renderInBackground(state_.editor.scene(), state_.frame);
        state_.showNote("rendering to " + state_.editor.scene().output.path + " ...");
    }
    ImGui::Render();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    glViewport(0, 0, fw, fh);
    glClearColor(0.1f, 0.1f, 0.11f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (!window_png_.empty()) {
        writeWindowPng(window_png_, fw, fh);
        window_png_.clear();
    }
    glfwSwapBuffers(window);
}

int ViewerApp::run(GLFWwindow* window) {
    const Scene& scene = state_.editor.scene();
    if (scene.volume().frames) {
        state_.first_frame = scene.volume().frames->first();
        state_.last_frame = scene.volume().frames->last();
        state_.frame = state_.first_frame;
    }
    state_.save_path = defaultSaveName(options_.source);
    state_.readVolumeBoxes();
    state_.updateBounds();
    state_.frame_cache_bytes = state_.frame ? options_.frame_cache_mb << 20 : 0;   // one frame needs no cache
    // The render wakes the UI when an image lands; the UI sleeps otherwise.
    state_.render = std::make_unique<ProgressiveRender>(scene, state_.frame, state_.frame_cache_bytes, [] { glfwPostEmptyEvent(); });
    state_.submitted_version = state_.editor.version();
    state_.submitted_frame = state_.frame;
    // SIGINT and SIGTERM wake the sleeping UI too: a signal handler may not call GLFW, so a thread
    // looks for one ten times a second (it costs nothing measurable).
    // A jthread: stopped and joined however the loop ends.
    const std::jthread signal_watch([](std::stop_token stop) {
        while (!stop.stop_requested()) {
            if (interruptSignal()) glfwPostEmptyEvent();
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    });
    auto last = Clock::now(), last_step = last;
    bool running = true;
    while (running && !glfwWindowShouldClose(window)) {
        // SIGINT or SIGTERM closes the window as its close button does; the watcher wakes the
        // idle wait below within 0.1 s, so a signal is seen that soon.
        if (const int signal = interruptSignal()) {
            exit_code_ = 128 + signal;
            break;
        }
        // Busy, the loop draws at most kFrameRate frames a second and leaves the rest of the CPU to
        // the render; idle, it sleeps until an event: input, a new image (the render posts one),
        // a signal. A few frames follow each event, so hover and release states settle.
        const bool busy = !script_.empty() || !state_.render->settled() || state_.playing || rendering_.valid() ||
                          ImGui::IsAnyMouseDown() || keys_.pending();
        const auto next_frame = last + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / kFrameRate));
        if (!busy && settle_frames_ == 0) {
            glfwWaitEvents();
            settle_frames_ = kSettleFrames;
        } else if (!busy) {
            glfwPollEvents();
            --settle_frames_;
        }
        for (auto now = Clock::now(); busy && now < next_frame; now = Clock::now())
            glfwWaitEventsTimeout(std::chrono::duration<double>(next_frame - now).count());
        if (busy) glfwPollEvents();
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last).count();
        last = now;
        state_.ui_fps = state_.ui_fps == 0.0 ? 1.0 / std::max(dt, 1e-6) : 0.9 * state_.ui_fps + 0.1 / std::max(dt, 1e-6);
        state_.slowest_ui_frame = std::max(state_.slowest_ui_frame, dt);
        // Playback: at the sequence's fps through frames in the flipbook; a frame not in it is
        // rendered first (the step waits for it to converge).
        if (state_.playing) {
            const int next = *state_.frame >= state_.last_frame ? state_.first_frame : *state_.frame + 1;
            const bool ready = state_.flipbook.count(next) || state_.render->settled();
            if (ready && std::chrono::duration<double>(now - last_step).count() >= 1.0 / state_.fps()) {
                state_.showFrame(next);
                last_step = now;
            }
        }
        syncRender();
        if (next_ < script_.size() && drawn_) {   // after a frame: a layout or a screenshot needs one drawn
            try {
                running = runScript();
            } catch (const std::exception& e) {   // a file it cannot write, a render that fails
                std::cerr << "voxlux: error: " << e.what() << "\n";
                exit_code_ = kInputError;
                running = false;
            }
        }
        drawFrame(window);
        drawn_ = true;
    }
    for (auto* f : {&rendering_, &script_render_})
        if (f->valid()) f->wait();
    return exit_code_;
}

}  // namespace

int runViewer(const Scene& scene, const ViewerOptions& options) {
    std::vector<ViewAction> script;
    if (options.script) script = loadViewScript(*options.script);
    if (options.bench) script = benchActions(scene);
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) throw InputError("voxlux view: no display (DISPLAY is not set); run it on a desktop, or under xvfb-run for scripts");
    // Mesa's llvmpipe (GL without a GPU) rasterizes the window on a thread per core at the UI's
    // priority, which pre-empts the render's threads (nice 10). Drawn by the UI thread alone, the
    // bench's first and converged images came 1.2-1.9x sooner (docs/viewer.md). A GL march on
    // llvmpipe would lose its threads too, so not when the scene asks for GL (auto takes GL only
    // on a GPU), and a value the user set stands.
    if (scene.render.backend != Backend::Gl) setenv("LP_NUM_THREADS", "0", ThreadLimit::setRasterizerThreads());
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) throw InputError("voxlux view: cannot open the display " + std::string(display) + " (" + glfwProblem + ")");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* window = glfwCreateWindow(options.window.x, options.window.y, ("voxlux view - " + options.source).c_str(), nullptr, nullptr);
    if (!window) {
        glfwTerminate();
        throw InputError("voxlux view: cannot open an OpenGL 3.3 window (" + glfwProblem + ")");
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;   // the layout is fixed; nothing to remember
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330");
    int code = 0;
    {
        ViewerApp app(scene, options, std::move(script), window);
        code = app.run(window);
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return code;
}

}  // namespace voxlux
