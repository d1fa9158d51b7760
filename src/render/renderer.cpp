#include "render/renderer.h"

#include <atomic>
#include <cstdlib>
#include <filesystem>

#include "backend/backend_choice.h"
#include "core/error.h"
#include "core/frame_pattern.h"
#include "grade/color_stages.h"
#include "kernel/kernel_inputs.h"
#include "lighting/light_grid_stage.h"
#include "lighting/lighting_method.h"
#include "lighting/march_lighting.h"
#include "render/environment_lights.h"
#include "render/grade_stage.h"
#include "render/holdout_stage.h"
#include "render/march_stage.h"
#include "render/write_stage.h"
#include "scene/scene_json.h"
#include "volume/volume_stages.h"

namespace voxlux {

// The shared stages, every registered lighting method's, then the march reading the methods'
// outputs, the grade and the write.
struct Renderer::Stages {
    explicit Stages(std::optional<LoadedVolume> given) : load(given ? LoadStage(std::move(*given)) : LoadStage()) {}
    std::vector<Stage*> all() {
        std::vector<Stage*> out{&color_space, &color_transforms, &load, &transfer_2d, &brick, &classify, &holdout_meshes, &volumes, &empty_check, &camera, &holdouts, &light_grid};
        for (const auto& m : methods)
            for (Stage* s : m->stages()) out.push_back(s);
        out.insert(out.end(), {&march, &coverage, &grade, &write});
        return out;
    }
    std::vector<std::unique_ptr<LightingMethod>> makeMethods() {
        const SharedStages shared{color_space, [this] { return color_space.xyzToWorking(); }, brick, classify, volumes, camera, light_grid};
        std::vector<std::unique_ptr<LightingMethod>> out;
        for (const LightingMethodEntry& entry : lightingMethods()) out.push_back(entry.make(shared));
        return out;
    }
    std::vector<const MarchLightingStage*> marchInputs() const {
        std::vector<const MarchLightingStage*> out;
        for (const auto& m : methods)
            for (const MarchLightingStage* s : m->marchInputs()) out.push_back(s);
        return out;
    }

    ColorSpaceStage color_space;
    ColorTransformsStage color_transforms{color_space};
    LoadStage load;
    Transfer2dStage transfer_2d{load};
    BrickStage brick{transfer_2d};
    ClassifyStage classify{transfer_2d, brick};
    HoldoutMeshStage holdout_meshes;
    VolumesStage volumes{brick, classify, holdout_meshes};
    EmptyFrameStage empty_check{classify, volumes};
    CameraStage camera{transfer_2d, volumes};
    HoldoutStage holdouts{camera, holdout_meshes};
    LightGridStage light_grid{brick, classify, volumes};
    std::vector<std::unique_ptr<LightingMethod>> methods = makeMethods();
    MarchStage march{color_space, brick, classify, volumes, empty_check, camera, holdouts, marchInputs()};
    CoverageStage coverage{brick, classify, volumes, camera, holdouts};
    GradeStage grade{march, color_transforms};
    WriteStage write{grade, camera, color_transforms, coverage};
};

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

Renderer::Renderer(Scene scene)
    : scene_(withEnvironmentLights(renderedScene(std::move(scene)))), stages_(std::make_unique<Stages>(std::nullopt)), graph_(stages_->all()) {}

Renderer::Renderer(Scene scene, LoadedVolume volume, KernelBackend& backend)
    : scene_(withEnvironmentLights(renderedScene(std::move(scene)))), backend_(&backend), stages_(std::make_unique<Stages>(std::move(volume))), graph_(stages_->all()) {}

Renderer::~Renderer() = default;

void Renderer::keepReferenceSums(bool keep) { stages_->march.keepReferenceSums(keep); }

void Renderer::setScene(Scene scene) {
    if (owned_backend_ && scene.render.backend != scene_.render.backend) {
        owned_backend_.reset();
        backend_ = nullptr;
    }
    scene_ = withEnvironmentLights(renderedScene(std::move(scene)));
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
    const std::string file = frame ? expandFramePattern(scene_.volume().path, *frame) : scene_.volume().path;
    in["file"] = stages_->load.given() ? nlohmann::json{{"path", "grids in memory"}} : fileIdentity(file);
    in["frame"] = frame ? nlohmann::json(*frame) : nlohmann::json(nullptr);
    if (scene_.volumes.size() > 1) {   // of several, each one's (the first's is also `file`)
        nlohmann::json& files = in["volume_files"] = nlohmann::json::array();
        for (const VolumeSpec& v : scene_.volumes)   // (a mesh holdout's cells: its mesh's, in holdout_files)
            files.push_back(v.holdout_mesh ? nlohmann::json(nullptr) : fileIdentity(frame ? expandFramePattern(v.path, *frame) : v.path));
    }
    if (!scene_.holdouts.empty()) {   // the depth images and meshes of the frame
        nlohmann::json& files = in["holdout_files"] = nlohmann::json::array();
        for (const Holdout& h : scene_.holdouts) {
            const std::string& path = h.mesh.empty() ? h.depth : h.mesh;
            files.push_back(fileIdentity(frame ? expandFramePattern(path, *frame) : path));
            if (h.transform && !h.transform->chan.empty()) files.back()["chan"] = fileIdentity(h.transform->chan);
        }
    }
    for (const Light& l : scene_.lights)   // the maps' files: an edit of one re-reads it
        if (l.environment) in["environment_maps"].push_back(fileIdentity(l.environment->map));
    if (nlohmann::json placements = holdoutPlacements(scene_, frame.value_or(0)); !placements.is_null()) in["holdout_placements"] = placements;
    if (scene_.volume().transform && !scene_.volume().transform->chan.empty())
        in["transform_chan"] = fileIdentity(scene_.volume().transform->chan);
    if (scene_.camera && scene_.camera->file) in["camera_file"] = fileIdentity(scene_.camera->file->path);
    // Which march a light lights in (the light groups): derived from the lights' groups and
    // whether output.aovs asks for them, so that neither alone re-runs what reads it.
    const LightGroups groups = lightGroups(scene_);
    in["light_groups"] = {{"marches", lightGroupMarches(scene_)}};
    if (!groups.names.empty()) {
        in["light_groups"]["names"] = groups.names;
        in["light_groups"]["of_light"] = groups.of_light;
    }
    // Which volumes a light lights and which shadow it (light linking), as link sets: derived from
    // the lights' lists, so that reordering a list or renaming nothing re-runs nothing.
    const LightLinks links = lightLinks(scene_);
    in["light_links"] = {{"sets", links.sets.size()}};
    if (!links.sets.empty()) {
        in["light_links"]["of_light"] = links.of_light;
        for (const LinkSet& set : links.sets) {
            in["light_links"]["lit"].push_back(set.lit ? nlohmann::json(*set.lit) : nlohmann::json());
            in["light_links"]["shadows"].push_back(set.shadows ? nlohmann::json(*set.shadows) : nlohmann::json());
        }
    }
    const char* ocio = std::getenv("OCIO");
    in["ocio"] = ocio ? ocio : "";
    in["allow_empty"] = allow_empty;
    return doc;
}

FrameResult Renderer::runGraph(std::optional<int> frame, bool allow_empty, const std::vector<std::string>& targets) {
    FrameResult r;
    r.stages = graph_.run(scene_, document(frame, allow_empty), backend(), targets, r.reused, r.warnings, cancelled_, stage_start_);
    for (const StageReport& s : r.stages)
        if (s.status == StageStatus::Ran) r.stage_seconds.emplace_back(s.name, s.seconds);
    for (const auto& m : stages_->methods)
        if (auto update = m->lightUpdate(r.stages)) r.light_update = update;
    r.camera = stages_->camera.camera();
    // Of several volumes, the joined atlas the march reads (instances share their volume's bricks).
    const bool several = rendersAsSeveral(scene_);
    r.bricks = several ? stages_->volumes.bricks().pages.occupied : stages_->classify.pages().occupied;
    r.empty = noVisibleBricks(stages_->classify, stages_->volumes);
    r.atlas_bytes = several ? stages_->volumes.bricks().atlas.bytes() : stages_->brick.atlas().bytes();
    return r;
}

const std::vector<float>& Renderer::holdoutDepth() const { return stages_->holdouts.depth(); }

FrameResult Renderer::render(std::optional<int> frame, bool allow_empty) {
    FrameResult r = runGraph(frame, allow_empty, {"march", "grade"});
    r.image = stages_->grade.result();
    r.preview = stages_->grade.preview();
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
    r.image = stages_->grade.result();
    r.preview = stages_->grade.preview();
    r.path = stages_->write.path();
    r.preview_path = stages_->write.previewPath();
    r.deep_path = stages_->write.deepPath();
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

const std::vector<const MarchLightingStage*>& Renderer::lightingStages() const { return stages_->march.lightingStages(); }

}  // namespace voxlux
