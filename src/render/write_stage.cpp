#include "render/write_stage.h"

#include <filesystem>

#include "core/error.h"
#include "core/json_reader.h"
#include "scene/camera.h"
#include "io/deep_exr_writer.h"
#include "io/exr_writer.h"
#include "core/frame_pattern.h"
#include "io/png_writer.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace {

std::string framePath(const std::string& pattern, const nlohmann::json& frame) {
    return frame.is_number() ? expandFramePattern(pattern, frame.get<int>()) : pattern;
}

}  // namespace

std::vector<std::string> frameOutputPaths(const Scene& scene, std::optional<int> frame) {
    const auto expand = [&](const std::string& pattern) { return frame ? expandFramePattern(pattern, *frame) : pattern; };
    std::vector<std::string> paths{expand(scene.output.path)};
    if (!scene.output.preview.empty()) paths.push_back(expand(scene.output.preview));
    if (scene.output.deep) paths.push_back(voxlux::deepPath(paths[0]));
    return paths;
}

StageActivity WriteStage::activity(const Scene& s) const {
    return {true, "EXR, " + std::string(s.output.pixel_type == PixelType::Half ? "half" : "float") + ", " + s.output.compression +
                      (s.output.aovs.empty() ? "" : ", AOVs") + (s.output.deep ? ", a deep EXR" : "") +
                      (s.output.preview.empty() ? "" : ", and an 8-bit PNG preview")};
}

void WriteStage::run(StageRun& run) {
    const Scene& scene = run.scene({""});   // the EXR's metadata holds the whole scene's hash
    const nlohmann::json& frame = run.scene.value("/input/frame");
    const RenderImage& image = grade_.result();
    path_ = framePath(scene.output.path, frame);
    preview_path_.clear();
    makeOutputFolder(path_);

    ExrMetadata meta;
    const float aspect = float(scene.render.width) / float(scene.render.height);
    meta.world_to_camera = glm::inverse(cameraToWorld(camera_.camera()));
    meta.world_to_ndc = cameraProjection(camera_.camera(), aspect) * meta.world_to_camera;
    meta.scene_hash = sceneHash(scene);
    if (frame.is_number()) meta.frame = frame.get<int>();
    for (const StageReport& s : run.so_far)
        if (s.status == StageStatus::Ran) meta.stage_seconds.emplace_back(s.name, s.seconds);
    const ColorPipeline& cp = color_.pipeline();
    meta.color_space = cp.output_space;
    meta.color_config = cp.config_source;
    meta.exposure = scene.render.exposure;
    for (const LightGroupLayer& layer : image.light_groups) meta.light_groups.push_back("lightgroup." + layer.name);
    if (cp.output_chromaticities) {
        const Chromaticities& c = *cp.output_chromaticities;
        meta.chromaticities = {{c.red, c.green, c.blue, c.white}};
    }
    // A frame's outputs are written together or not at all: the preview and the deep image first,
    // and taken away again when the EXR cannot be written; the EXR last, as it marks the frame done
    // (--resume).
    if (!scene.output.preview.empty()) {
        preview_path_ = framePath(scene.output.preview, frame);
        makeOutputFolder(preview_path_);
        const PngWriteReport png = writePng(preview_path_, image.width, image.height, grade_.preview(), false);
        if (png.non_finite)
            run.warnings.push_back(preview_path_ + ": " + std::to_string(png.non_finite) + " non-finite samples written as 0");
    }
    ExrWriteReport written;
    deep_path_ = scene.output.deep ? voxlux::deepPath(path_) : "";
    try {
        if (!deep_path_.empty()) written = writeDeepExr(deep_path_, image, scene.output, meta);
        // Each volume's coverage: the coverage stage's planes, or one visible volume's alpha.
        std::vector<float> alpha;
        std::vector<ExrPlane> coverage;
        if (wantsCoverage(scene) && rendersAsSeveral(scene)) {
            for (size_t v = 0; v < coverage_.planes().names.size(); ++v) coverage.push_back({coverage_.planes().names[v], &coverage_.planes().planes[v]});
        } else if (wantsCoverage(scene)) {
            for (const kernel::VxPixel& p : image.pixels) alpha.push_back(p.rgba.w);
            coverage.push_back({scene.volume().name.empty() ? "volume" : scene.volume().name, &alpha});
        }
        const ExrWriteReport flat = writeExr(path_, image, scene.output, meta, coverage);
        written.non_finite += flat.non_finite;
        written.half_overflow += flat.half_overflow;
    } catch (const InputError&) {
        std::error_code ec;
        if (!preview_path_.empty()) std::filesystem::remove(preview_path_, ec);
        if (!deep_path_.empty()) std::filesystem::remove(deep_path_, ec);
        throw;
    }
    if (written.non_finite)
        run.warnings.push_back(path_ + ": " + std::to_string(written.non_finite) + " non-finite samples written as 0");
    if (written.half_overflow)
        run.warnings.push_back(path_ + ": " + std::to_string(written.half_overflow) +
                               " samples above the half-float range clamped to 65504 (use output.pixel_type \"float\")");
}

std::string sceneHash(const Scene& scene) {
    // The scene as its file says: what the renderer derives from it (its disabled volumes left
    // out, a mesh holdout's cells, an environment's median-cut lights) is not hashed, so a frame
    // carries the hash its scene file gives.
    Scene own = withEnabledVolumes(scene);
    std::erase_if(own.volumes, [](const VolumeSpec& v) { return v.holdout_mesh.has_value(); });
    std::erase_if(own.lights, [](const Light& l) { return l.from_environment.has_value(); });
    nlohmann::json j = sceneToJson(scenePathsRelativeTo(std::move(own), "/"));
    for (auto& v : j["volumes"]) v.erase("frames");
    j["output"].erase("path");
    j["output"].erase("preview");
    return hashText(jsonText(j));
}

}  // namespace voxlux
