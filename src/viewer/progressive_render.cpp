#include "viewer/progressive_render.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <exception>
#include <limits>

#include <tbb/task_scheduler_observer.h>

#include "core/error.h"
#include "io/png_writer.h"

namespace voxlux {

namespace {

// Renders yield to the UI: the worker and every TBB thread run at nice 10, so on a machine with
// as many busy threads as cores the UI thread still gets the time for its frames (at nice 0 it
// weighs about 10 times a nice-10 thread in Linux's scheduler).
constexpr int kRenderNice = 10;
void lowerThisThread() { setpriority(PRIO_PROCESS, id_t(syscall(SYS_gettid)), kRenderNice); }

class LowerTbbThreads final : public tbb::task_scheduler_observer {
public:
    LowerTbbThreads() { observe(true); }
    ~LowerTbbThreads() override { observe(false); }
    void on_scheduler_entry(bool worker) override {
        if (worker) lowerThisThread();
    }
};

}  // namespace

std::vector<uint8_t> opaqueTexels(const std::vector<glm::vec4>& display) {
    std::vector<uint8_t> texels(display.size() * 4);
    for (size_t i = 0; i < display.size(); ++i) {
        for (int c = 0; c < 3; ++c) texels[i * 4 + c] = displayByte(display[i][c]);
        texels[i * 4 + 3] = 255;
    }
    return texels;
}

void drawHoldoutSilhouettes(std::vector<uint8_t>& texels, const std::vector<glm::vec4>& display, const std::vector<float>& depth) {
    if (depth.size() != display.size()) return;   // no holdouts
    for (size_t i = 0; i < display.size(); ++i) {
        if (depth[i] == std::numeric_limits<float>::max()) continue;
        for (int c = 0; c < 3; ++c) texels[i * 4 + c] = displayByte(display[i][c] + (1.0f - display[i].w) * kHoldoutGrey);
    }
}

glm::ivec2 levelResolution(glm::ivec2 full, int divisor) {
    return glm::max(glm::ivec2(1), (full + glm::ivec2(divisor - 1)) / divisor);
}

std::vector<ViewLevel> progressiveLevels(const Scene& scene) {
    const bool reference = scene.render.method == RenderMethod::Reference;
    std::vector<ViewLevel> levels;
    for (int d : kProgressiveDivisors)   // a level is worth its march when it is at least 32 pixels wide
        if (d == 1 || scene.render.width / d >= 32) levels.push_back({d, reference ? 1 : 0});
    if (reference) {   // then the samples, doubling, each added to the last
        const int target = scene.render.reference.spp;
        for (int s = 2; s < target; s *= 2) levels.push_back({1, s});
        if (target > 1) levels.push_back({1, target});
    }
    return levels;
}

ProgressiveRender::ProgressiveRender(Scene scene, std::optional<int> frame, size_t cache_bytes, std::function<void()> on_change)
    : cache_bytes_(cache_bytes), on_change_(std::move(on_change)) {
    submit(std::move(scene), frame);
    worker_ = std::thread([this] { work(); });
}

ProgressiveRender::~ProgressiveRender() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        cancelled_ = true;
        if (march_context_) march_context_->cancel_group_execution();
    }
    wake_.notify_all();
    worker_.join();
}

uint64_t ProgressiveRender::submit(Scene scene, std::optional<int> frame) {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_scene_ = std::move(scene);
    pending_frame_ = frame;
    submit_time_ = std::chrono::steady_clock::now();
    ++stats_.submitted;
    if (march_context_) {   // the march in flight is for an older edit
        cancelled_ = true;
        march_context_->cancel_group_execution();
    }
    wake_.notify_all();
    return ++submitted_;
}

std::shared_ptr<const ViewFrame> ProgressiveRender::latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
}

std::optional<ProgressiveRender::Failure> ProgressiveRender::failure() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return failure_;
}

ViewStatistics ProgressiveRender::statistics() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return stats_;
}

bool ProgressiveRender::waitConverged(double seconds) {
    std::unique_lock<std::mutex> lock(mutex_);
    return settled_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return settled_edit_ == submitted_; });
}

bool ProgressiveRender::settled() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return settled_edit_ == submitted_;
}

bool ProgressiveRender::newerEdit() const { return stop_ || started_ != submitted_; }

void ProgressiveRender::work() {
    lowerThisThread();
    static LowerTbbThreads lower_tbb;   // once per process: TBB's threads are shared
    std::unique_ptr<Renderer> renderer;   // made here, so a GL backend's context belongs to this thread
    for (;;) {
        Scene scene;
        std::optional<int> frame;
        uint64_t edit = 0;
        std::chrono::steady_clock::time_point since;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [this] { return stop_ || started_ != submitted_; });
            if (stop_) return;
            scene = pending_scene_;
            frame = pending_frame_;
            edit = started_ = submitted_;
            since = submit_time_;
            cancelled_ = false;   // a cancel was for an older edit
        }
        if (!renderer) {
            renderer = std::make_unique<Renderer>(scene);
            renderer->setCancellation([this] { return cancelled_.load(); });
            renderer->keepReferenceSums(true);
            renderer->setCacheBudget(cache_bytes_);
        }
        try {
            renderEdit(*renderer, scene, frame, edit, since);
        } catch (const Cancelled&) {   // a newer edit came: it is next
            std::lock_guard<std::mutex> lock(mutex_);
            ++stats_.cancelled;
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(mutex_);
            failure_ = Failure{edit, e.what(), false, last_good_.value_or(scene), last_good_ ? last_good_frame_ : frame};
            // Show the last good state again, unless the user has moved on already, or this was
            // that re-render failing (a file removed since): then the failure stands.
            if (last_good_ && started_ == submitted_ && edit != restore_edit_) {
                pending_scene_ = *last_good_;
                pending_frame_ = last_good_frame_;
                restore_edit_ = ++submitted_;
                failure_->restored = true;
            }
            settled_edit_ = edit;
            settled_.notify_all();
        }
        if (on_change_) on_change_();   // an edit settled, failed or was cancelled: the UI shows it
    }
}

void ProgressiveRender::renderEdit(Renderer& renderer, const Scene& scene, std::optional<int> frame, uint64_t edit,
                                   std::chrono::steady_clock::time_point since) {
    const glm::ivec2 full(scene.render.width, scene.render.height);
    const std::vector<ViewLevel> levels = progressiveLevels(scene);

    // The grade stage makes the display-referred image only for a scene with a preview; the
    // path is never written (the viewer runs no write stage).
    Scene shown = scene;
    if (shown.output.preview.empty()) shown.output.preview = "viewer.png";
    shown.output.deep = false;   // the viewer shows the flat image; deep samples would only cost
    shown.render.motion_blur.reset();   // the frame's own time: navigation moves the camera, not its shutter poses

    // The lighting first, at full resolution, never cancelled: a light drag's next edit then
    // starts from this one's illumination and stays a selective update.
    renderer.setScene(shown);
    const FrameResult prepared = renderer.prepare(frame, true);
    ViewFrame base;
    base.edit = edit;
    base.frame = frame;
    base.levels = int(levels.size());
    base.light_update = prepared.light_update;
    for (const StageReport& s : prepared.stages)
        if (s.status == StageStatus::Ran || s.cached) base.edit_stages.push_back(s);
    base.cache_bytes = renderer.graph().cache().bytes();
    base.cache_outputs = renderer.graph().cache().entries();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (prepared.light_update) {
            stats_.selective_updates += prepared.light_update->mode == LightUpdate::Mode::Selective;
            stats_.entire_updates += prepared.light_update->mode == LightUpdate::Mode::Entire;
            stats_.kept_updates += prepared.light_update->mode == LightUpdate::Mode::Kept;
        }
    }

    for (size_t k = 0; k < levels.size(); ++k) {
        Scene level = shown;
        const glm::ivec2 size = levelResolution(full, levels[k].divisor);
        level.render.width = size.x;
        level.render.height = size.y;
        if (levels[k].samples > 0) level.render.reference.spp = levels[k].samples;
        renderer.setScene(level);

        FrameResult r;
        std::exception_ptr error;
        tbb::task_group_context context;
        tbb::task_group group(context);
        {   // one lock: a submit either comes before (and this edit stops) or sees the context to cancel
            std::lock_guard<std::mutex> lock(mutex_);
            if (newerEdit()) return;
            cancelled_ = false;
            march_context_ = &context;
        }
        // Exceptions are caught inside: TBB drops one thrown in a group that was cancelled.
        group.run_and_wait([&] {
            try {
                r = renderer.render(frame, true);
            } catch (...) {
                error = std::current_exception();
            }
        });
        {
            std::lock_guard<std::mutex> lock(mutex_);
            march_context_ = nullptr;
            if (cancelled_) {
                ++stats_.cancelled;
                return;
            }
        }
        if (error) std::rethrow_exception(error);

        auto out = std::make_shared<ViewFrame>(base);
        out->level = int(k);
        out->converged = k + 1 == levels.size();
        out->samples = levels[k].samples;
        out->camera = r.camera;
        out->image = std::move(r.image);
        out->display = std::move(r.preview);
        out->display_texels = opaqueTexels(out->display);
        drawHoldoutSilhouettes(out->display_texels, out->display, renderer.holdoutDepth());
        out->warnings = std::move(r.warnings);
        if (k == 0)
            for (const StageReport& s : r.stages)
                if (s.status == StageStatus::Ran) out->edit_stages.push_back(s);
        std::lock_guard<std::mutex> lock(mutex_);
        out->seconds_to_image = std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
        if (k == 0) {
            base.edit_stages = out->edit_stages;
            ++stats_.rendered;
            stats_.first_image_seconds = out->seconds_to_image;
        }
        latest_ = out;
        if (out->converged) {
            last_good_ = scene;
            last_good_frame_ = frame;
            ++stats_.converged;
            stats_.converged_seconds = out->seconds_to_image;
            settled_edit_ = edit;
            settled_.notify_all();
        }
        if (on_change_) on_change_();
    }
}

}  // namespace voxlux
