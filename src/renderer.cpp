#include "renderer.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "brick_atlas.h"
#include "camera.h"
#include "error.h"
#include "exr_writer.h"
#include "frame_pattern.h"
#include "grade_stage.h"
#include "kernel_inputs.h"
#include "page_table.h"
#include "png_writer.h"
#include "reference_renderer.h"
#include "scene_json.h"
#include "stage_clock.h"
#include "vdb_loader.h"

namespace voxlux {
namespace {

std::string emptyReason(const LoadedVolume& v, const BrickAtlas& atlas) {
    std::string grid = "grid '" + v.density->getName() + "'";
    if (atlas.active_voxels == 0) return v.file + ": " + grid + " has no active voxels";
    std::string why = v.file + ": " + grid + " has nothing visible: its " + std::to_string(atlas.active_voxels) +
                      " active voxels are all zero";
    if (atlas.density_fixes.negative) why += " or negative (" + std::to_string(atlas.density_fixes.negative) + " negative)";
    why += " under the material";
    for (size_t e = 0; e < v.emission.size(); ++e) why += (e ? ", '" : "; emission from '") + v.emission[e]->getName() + "'";
    return why + (v.emission.empty() ? "" : " emits nothing");
}

}  // namespace

Camera frameActiveVoxels(const LoadedVolume& volume, const RenderSettings& render) {
    openvdb::CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    glm::vec3 lo(0.0f), hi(1.0f);
    if (!box.empty())
        worldBounds(volume.index_to_world, glm::vec3(box.min().x(), box.min().y(), box.min().z()),
                    glm::vec3(box.max().x(), box.max().y(), box.max().z()), lo, hi);
    return frameBox(lo, hi, Camera{}.fov, float(render.width) / float(render.height));
}

Camera frameVolumeCamera(const std::string& file, const Scene& scene) {
    auto volume = loadVolume(file, scene.volume);
    if (volume.density->activeVoxelCount() == 0)
        throw InputError(file + ": grid '" + volume.density->getName() + "' has no active voxels");
    return frameActiveVoxels(volume, scene.render);
}

Renderer::Renderer(Scene scene)
    : scene_(std::move(scene)), plan_(planRender(scene_)), backend_(makeBackend(scene_.render.backend)) {}

void Renderer::setScene(Scene scene) {
    if (scene.render.backend != scene_.render.backend) backend_ = makeBackend(scene.render.backend);
    scene_ = std::move(scene);
    plan_ = planRender(scene_);
}

// The file's identity (path, size, modification time) and how it is read: equal keys mean equal
// bricks, so the load and brick stages can be skipped.
std::string Renderer::volumeKey(const std::string& file) const {
    std::error_code ec;
    const auto size = std::filesystem::file_size(file, ec);
    if (ec) return "";
    const auto time = std::filesystem::last_write_time(file, ec);
    if (ec) return "";
    const nlohmann::json scene = sceneToJson(scene_);
    nlohmann::json spec = scene["volume"];
    spec.erase("frames");
    for (const auto& e : scene["emission"]) spec["emission"].push_back(e["grid"]);  // one atlas channel each
    return file + "|" + std::to_string(size) + "|" + std::to_string(time.time_since_epoch().count()) + "|" + spec.dump();
}

const ColorPipeline& Renderer::color() {
    const char* env = std::getenv("OCIO");
    const std::string key = sceneToJson(scene_)["color"].dump() + "|" + (env ? env : "") + "|" + scene_.output.preview;
    if (!color_ || key != color_key_) {
        color_.reset();
        color_ = buildColorPipeline(scene_.color, !scene_.output.preview.empty());
        color_key_ = key;
    }
    return *color_;
}

// Blackbody colours are computed in CIE XYZ and need the config's way into the working space.
glm::mat3 Renderer::xyzToWorking() {
    const ColorPipeline& cp = color();
    if (cp.xyz_to_working) return *cp.xyz_to_working;
    for (const auto& e : scene_.emission)
        if (e.kind == EmissionKind::Blackbody)
            throw InputError(cp.config_source + ": has no linear cie_xyz_d65_interchange role into '" + cp.working_space +
                             "', which blackbody emission needs");
    return glm::mat3(1.0f);  // unused: no source converts from XYZ
}

FrameResult Renderer::render(std::optional<int> frame, bool allow_empty) {
    FrameResult r;
    KernelInputs inputs = runStages(frame, allow_empty, r);
    StageClock clock(r.stage_seconds);
    r.image = clock("march", [&] {
        return scene_.render.method == RenderMethod::Reference ? renderReference(inputs, scene_.render.reference)
                                                               : backend_->march(inputs);
    });
    if (stageRuns(plan_, "grade")) {
        std::vector<std::string> aovs;
        for (const auto& aov : scene_.output.aovs) aovs.push_back(aov.name);
        r.preview = clock("grade", [&] { return gradeImage(r.image, color(), aovs, *backend_); });
    }
    return r;
}

FrameResult Renderer::prepare(std::optional<int> frame, bool allow_empty) {
    FrameResult r;
    runStages(frame, allow_empty, r);
    return r;
}

KernelInputs Renderer::runStages(std::optional<int> frame, bool allow_empty, FrameResult& r) {
    xyzToWorking();  // a bad config, space or look fails here, before any volume is read
    StageClock clock(r.stage_seconds);
    const std::string file = frame ? expandFramePattern(scene_.volume.path, *frame) : scene_.volume.path;

    const std::string key = volumeKey(file);
    if (key.empty() || key != volume_key_) {
        volume_key_.clear();  // stays cleared if loading throws
        atlas_.reset();       // the last frame's bricks go before this frame's are built
        volume_.reset();
        volume_ = std::make_unique<LoadedVolume>(clock("load", [&] { return loadVolume(file, scene_.volume, scene_.emission); }));
        atlas_ = std::make_unique<BrickAtlas>(clock("brick", [&] { return buildBrickAtlas(*volume_); }));
        volume_key_ = key;
    } else {
        r.reused = {"load", "brick"};
    }
    const LoadedVolume& volume = *volume_;
    const BrickAtlas& atlas = *atlas_;
    r.warnings = volume.warnings;
    for (auto& line : sanitizeReport(atlas, volume)) r.warnings.push_back(line);
    pages_ = clock("classify", [&] {
        return buildPageTable(atlas.coords, classifyBricks(atlas, scene_.material, scene_.emission));
    });
    const PageTable& pages = pages_;
    r.bricks = pages.occupied;
    r.atlas_bytes = atlas.bytes();
    if (pages.empty()) {
        if (!allow_empty) throw InputError(emptyReason(volume, atlas));
        r.warnings.push_back(emptyReason(volume, atlas) + "; rendered as an empty frame");
        r.empty = true;
    }

    r.camera = scene_.camera ? *scene_.camera : frameActiveVoxels(volume, scene_.render);
    KernelInputs inputs = makeKernelInputs(scene_, r.camera, atlas, pages, frame ? float(*frame) : 0.0f, xyzToWorking());
    if (stageRuns(plan_, "light_cache") && !pages.empty())
        light_.update(scene_, key, inputs, *backend_, r.stage_seconds, r.reused, r.warnings);
    if (stageRuns(plan_, "illumination") && !pages.empty()) {
        illumination_.update(scene_, r.camera, key, inputs, *backend_, r.stage_seconds, r.reused, r.warnings);
        r.light_update = illumination_.lastUpdate();
    }
    return inputs;
}

FrameResult Renderer::renderToFile(std::optional<int> frame, bool allow_empty) {
    if (scene_.output.path.empty()) throw InputError("no output path: pass -o FILE.exr or set output.path in the scene");
    FrameResult r = render(frame, allow_empty);
    const std::string path = frame ? expandFramePattern(scene_.output.path, *frame) : scene_.output.path;
    r.path = path;
    std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);

    ExrMetadata meta;
    const float aspect = float(scene_.render.width) / float(scene_.render.height);
    meta.world_to_camera = glm::inverse(cameraToWorld(r.camera));
    meta.world_to_ndc = cameraProjection(r.camera, aspect) * meta.world_to_camera;
    meta.scene_hash = sceneHash(scene_);
    meta.frame = frame;
    meta.stage_seconds = r.stage_seconds;
    const ColorPipeline& cp = color();
    meta.color_space = cp.output_space;
    meta.color_config = cp.config_source;
    if (cp.output_chromaticities) {
        const Chromaticities& c = *cp.output_chromaticities;
        meta.chromaticities = {{c.red, c.green, c.blue, c.white}};
    }
    StageClock clock(r.stage_seconds);
    ExrWriteReport written = clock("write", [&] { return writeExr(path, r.image, scene_.output, meta); });
    if (!scene_.output.preview.empty()) {
        r.preview_path = frame ? expandFramePattern(scene_.output.preview, *frame) : scene_.output.preview;
        const std::filesystem::path folder = std::filesystem::path(r.preview_path).parent_path();
        if (!folder.empty()) std::filesystem::create_directories(folder, ec);
        PngWriteReport png = clock("preview", [&] {
            return writePng(r.preview_path, r.image.width, r.image.height, r.preview, false);
        });
        if (png.non_finite)
            r.warnings.push_back(r.preview_path + ": " + std::to_string(png.non_finite) + " non-finite samples written as 0");
    }
    if (written.non_finite)
        r.warnings.push_back(path + ": " + std::to_string(written.non_finite) + " non-finite samples written as 0");
    if (written.half_overflow)
        r.warnings.push_back(path + ": " + std::to_string(written.half_overflow) +
                             " samples above the half-float range clamped to 65504 (use output.pixel_type \"float\")");
    return r;
}

std::string sceneHash(const Scene& scene) {
    const std::string text = sceneToJson(scene).dump();
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : text) {
        h ^= c;
        h *= 1099511628211ull;
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

}  // namespace voxlux
