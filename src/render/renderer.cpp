#include "render/renderer.h"

#include <atomic>
#include <cstdlib>
#include <filesystem>

#include "backend/backend_choice.h"
#include "core/error.h"
#include "core/frame_pattern.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace {

// The file's identity: equal identities (path, size, modification time) mean equal grids, so the
// load and brick stages can be kept. A file that cannot be read gets an identity of its own, so
// the load stage runs and names the problem.
nlohmann::json fileIdentity(const std::string& file) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(file, ec);
    const auto time = ec ? std::filesystem::file_time_type{} : std::filesystem::last_write_time(file, ec);
    if (ec) {
        static std::atomic<long> unreadable{0};   // the viewer renders on two threads
        return {{"path", file}, {"unreadable", ++unreadable}};
    }
    return {{"path", file}, {"size", size}, {"time", time.time_since_epoch().count()}};
}

}  // namespace

Renderer::Renderer(Scene scene) : scene_(std::move(scene)) {}

Renderer::Renderer(Scene scene, LoadedVolume volume, KernelBackend& backend)
    : scene_(std::move(scene)),
      backend_(&backend),
      load_(std::move(volume)) {}

void Renderer::setScene(Scene scene) {
    if (owned_backend_ && scene.render.backend != scene_.render.backend) {
        owned_backend_.reset();
        backend_ = nullptr;
    }
    scene_ = std::move(scene);
}

KernelBackend& Renderer::backend() {
    if (!backend_) {
        owned_backend_ = makeBackend(scene_.render.backend);
        backend_ = owned_backend_.get();
    }
    return *backend_;
}

nlohmann::json Renderer::document(std::optional<int> frame, bool allow_empty) const {
    nlohmann::json doc = sceneToJson(scene_);
    nlohmann::json& in = doc["input"];
    const std::string file = frame ? expandFramePattern(scene_.volume.path, *frame) : scene_.volume.path;
    in["file"] = load_.given() ? nlohmann::json{{"path", "grids in memory"}} : fileIdentity(file);
    in["frame"] = frame ? nlohmann::json(*frame) : nlohmann::json(nullptr);
    const char* ocio = std::getenv("OCIO");
    in["ocio"] = ocio ? ocio : "";
    in["allow_empty"] = allow_empty;
    return doc;
}

FrameResult Renderer::runGraph(std::optional<int> frame, bool allow_empty, const std::vector<std::string>& targets) {
    FrameResult r;
    r.stages = graph_.run(scene_, document(frame, allow_empty), backend(), targets, r.reused, r.warnings, cancelled_, stage_start_);
    for (const StageReport& s : r.stages) {
        if (s.status == StageStatus::Ran) r.stage_seconds.emplace_back(s.name, s.seconds);
        if (s.name == "propagation" && s.status == StageStatus::Ran) r.light_update = propagation_.lastUpdate();
        if (s.name == "propagation" && s.status == StageStatus::Reused) {
            LightUpdate kept;   // nothing the sweeps read changed
            kept.mode = LightUpdate::Mode::Kept;
            kept.lights = propagation_.lastUpdate().lights;
            r.light_update = kept;
        }
    }
    r.camera = camera_.camera();
    r.bricks = classify_.pages().occupied;
    r.empty = classify_.pages().empty();
    r.atlas_bytes = brick_.atlas().bytes();
    return r;
}

FrameResult Renderer::render(std::optional<int> frame, bool allow_empty) {
    FrameResult r = runGraph(frame, allow_empty, {"march", "grade"});
    r.image = grade_.result();
    r.preview = grade_.preview();
    return r;
}

FrameResult Renderer::prepare(std::optional<int> frame, bool allow_empty) {
    return runGraph(frame, allow_empty, {"color_transforms", "empty_check", "camera", "light_cache", "eye_pass"});
}

std::optional<std::string> outputPathProblem(const Scene& scene) {
    if (!scene.output.path.empty()) return std::nullopt;
    return "no output path: pass -o FILE.exr or set output.path in the scene";
}

FrameResult Renderer::renderToFile(std::optional<int> frame, bool allow_empty) {
    if (const auto problem = outputPathProblem(scene_)) throw InputError(*problem);
    FrameResult r = runGraph(frame, allow_empty, {"write"});
    r.image = grade_.result();
    r.preview = grade_.preview();
    r.path = write_.path();
    r.preview_path = write_.previewPath();
    r.deep_path = write_.deepPath();
    return r;
}

std::string writtenFilesText(const FrameResult& r) {
    std::vector<std::string> files{r.path};
    for (const std::string* p : {&r.deep_path, &r.preview_path})
        if (!p->empty()) files.push_back(*p);
    std::string text = files[0];
    for (size_t k = 1; k < files.size(); ++k) text += (k + 1 == files.size() ? " and " : ", ") + files[k];
    return text;
}

const IlluminationVolume* Renderer::illumination() const {
    if (!eye_pass_.volume().values.empty()) return &eye_pass_.volume();
    return propagation_.volume().values.empty() ? nullptr : &propagation_.volume();
}

const LightCache* Renderer::lightCache() const { return light_cache_.cache().channels > 0 ? &light_cache_.cache() : nullptr; }

}  // namespace voxlux
