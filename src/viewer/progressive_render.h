// The viewer's renders, off the UI thread: a worker owns a Renderer (the render graph of `voxlux
// render`) and renders the newest submitted scene progressively, at 1/8, 1/4 and 1/2 of its
// resolution and then in full (the reference then adds samples until it has the scene's),
// publishing each image as it lands. A submit cancels the march in
// flight (TBB cancellation; the graph drops the cancelled stage's output) and restarts from the
// coarsest level; a lighting update in flight is let finish, so a light drag stays a run of
// selective updates (Sunden 2015) rather than restarts of the whole sweep. Edits that arrive
// meanwhile are coalesced: only the newest is rendered.
// Cost: the levels below full add about 1/64 + 1/16 + 1/4 of a full march to a converged image.
// The eye pass (effects.propagation.eye_pass) reads the camera, whose resolution each level
// changes: it runs again at every level, inside the cancellable part.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/task_group.h>

#include "render/renderer.h"
#include "scene/scene.h"

namespace voxlux {

// The resolution divisors of the progressive levels, coarsest first; the last is the full image.
inline constexpr int kProgressiveDivisors[] = {8, 4, 2, 1};

// The image size at `divisor` of `full` (each side rounded up, at least 1 pixel).
glm::ivec2 levelResolution(glm::ivec2 full, int divisor);

// One image of an edit's progression: a resolution divisor and, for the Monte Carlo reference,
// the samples a pixel (0: the scene's).
struct ViewLevel {
    int divisor = 1;
    int samples = 0;
};
// The levels of `scene`: each divisor whose image is at least 32 pixels wide, and the full image;
// for the reference those at 1 sample a pixel, then the full image at 2, 4, 8, ... samples and at
// render.reference.spp, each level's samples added to the last's (MarchStage::keepReferenceSums).
std::vector<ViewLevel> progressiveLevels(const Scene& scene);

// One published image.
struct ViewFrame {
    uint64_t edit = 0;                       // the submit it renders (1 for the first)
    int level = 0;                           // index into the levels run for this edit
    int levels = 1;
    bool converged = false;                  // the last level of the edit
    int samples = 0;                         // reference samples a pixel (0 for the march)
    std::optional<int> frame;                // the sequence frame rendered
    Camera camera;                           // as rendered (the scene's, or the framing's)
    RenderImage image;                       // scene-linear, graded into the output space
    std::vector<glm::vec4> display;          // display-referred RGBA through the scene's view
    std::vector<uint8_t> display_texels;     // the same as the viewport's texture (opaqueTexels), made
                                             // by the worker: at 1280x720 the conversion would hold
                                             // the UI thread for a frame or two
    std::vector<StageReport> edit_stages;    // what the edit re-ran (its lighting update and first march)
                                             // and took back from the frame cache
    std::optional<LightUpdate> light_update; // the propagation stage's update for the edit, if it ran
    double seconds_to_image = 0.0;           // from the submit to this image
    size_t cache_bytes = 0, cache_outputs = 0;   // held by the frame cache after the edit's lighting
    std::vector<std::string> warnings;
};

// Display-referred RGBA as 8-bit RGBA texels, each channel as the PNG preview stores it
// (displayByte), alpha opaque, since the viewport draws the preview over black as the
// PNG does.
std::vector<uint8_t> opaqueTexels(const std::vector<glm::vec4>& display);

// The holdouts' CG as a dark grey silhouette behind the volume, where a holdout stands (`depth`:
// Renderer::holdoutDepth) and as much as the volume in front lets through: the render holds the CG
// out as black, the black of the viewport, and the artist would not see where it stands.
constexpr float kHoldoutGrey = 0.18f;   // display-referred
void drawHoldoutSilhouettes(std::vector<uint8_t>& texels, const std::vector<glm::vec4>& display, const std::vector<float>& depth);

// What the worker did since it started: counts a test or benchmark reads.
struct ViewStatistics {
    uint64_t submitted = 0;
    uint64_t rendered = 0;          // edits that reached their first image
    uint64_t converged = 0;         // edits that reached full resolution
    uint64_t cancelled = 0;         // marches stopped by a newer edit
    uint64_t selective_updates = 0; // propagation updates by mode
    uint64_t entire_updates = 0;
    uint64_t kept_updates = 0;
    double first_image_seconds = 0.0;   // of the newest edit that reached its first image: submit to image
    double converged_seconds = 0.0;     // of the newest edit that converged
};

class ProgressiveRender {
public:
    // `frame` as in Renderer::render. The first scene is rendered at once. The grids and bricks of
    // frames rendered before are kept within `cache_bytes` (Renderer::setCacheBudget), so that
    // scrubbing back to a frame runs neither load nor brick.
    // `on_change`, when given, is called from the worker after each image lands and each edit
    // settles or fails: the UI sleeps until then (glfwPostEmptyEvent wakes it).
    ProgressiveRender(Scene scene, std::optional<int> frame, size_t cache_bytes = 0, std::function<void()> on_change = {});
    ~ProgressiveRender();
    ProgressiveRender(const ProgressiveRender&) = delete;
    ProgressiveRender& operator=(const ProgressiveRender&) = delete;

    // Renders `scene` (a full-resolution scene as a user edits it) instead of what was asked
    // before. Returns the edit's number.
    uint64_t submit(Scene scene, std::optional<int> frame);

    // The newest image, or null before the first one. Thread-safe; the frame is never changed.
    std::shared_ptr<const ViewFrame> latest() const;

    // The one-line error of the newest edit that failed (a missing file, a grid that is not
    // there), or nothing. When no newer edit was waiting, the worker renders the last scene that
    // converged again (`restored`), which the UI then shows as its state.
    struct Failure {
        uint64_t edit = 0;
        std::string message;
        bool restored = false;
        Scene last_good;
        std::optional<int> last_good_frame;
    };
    std::optional<Failure> failure() const;

    // Blocks until the newest edit (the last good scene's re-render, after a failure) has converged
    // or failed, or `seconds` passed; true if it did.
    bool waitConverged(double seconds);
    // Whether the newest edit has converged or failed.
    bool settled() const;
    ViewStatistics statistics() const;

private:
    void work();
    void renderEdit(Renderer& renderer, const Scene& scene, std::optional<int> frame, uint64_t edit,
                    std::chrono::steady_clock::time_point since);
    bool newerEdit() const;   // with mutex_ held

    mutable std::mutex mutex_;
    std::condition_variable wake_, settled_;
    Scene pending_scene_;
    std::optional<int> pending_frame_;
    uint64_t submitted_ = 0, started_ = 0, settled_edit_ = 0;
    std::chrono::steady_clock::time_point submit_time_;
    bool stop_ = false;
    const size_t cache_bytes_;
    const std::function<void()> on_change_;
    tbb::task_group_context* march_context_ = nullptr;   // the march in flight, to cancel
    std::atomic<bool> cancelled_{false};
    std::shared_ptr<const ViewFrame> latest_;
    std::optional<Failure> failure_;
    std::optional<Scene> last_good_;          // the newest scene that converged, and its frame
    std::optional<int> last_good_frame_;
    uint64_t restore_edit_ = 0;               // the edit that re-renders the last good scene
    ViewStatistics stats_;
    std::thread worker_;
};

}  // namespace voxlux
