#include "renderer.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "brick_atlas.h"
#include "camera.h"
#include "error.h"
#include "exr_writer.h"
#include "frame_pattern.h"
#include "kernel_inputs.h"
#include "page_table.h"
#include "scene_json.h"
#include "vdb_loader.h"

namespace voxlux {
namespace {

// Runs one stage and appends its wall time to `out`.
class StageClock {
public:
    explicit StageClock(std::vector<std::pair<std::string, double>>& out) : out_(out) {}
    template <typename F>
    auto operator()(const std::string& stage, F&& work) {
        auto start = std::chrono::steady_clock::now();
        auto result = work();
        out_.emplace_back(stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        return result;
    }

private:
    std::vector<std::pair<std::string, double>>& out_;
};

std::string emptyReason(const LoadedVolume& v, const BrickAtlas& atlas) {
    std::string grid = "grid '" + v.density->getName() + "'";
    if (atlas.active_voxels == 0) return v.file + ": " + grid + " has no active voxels";
    std::string why = v.file + ": " + grid + " has nothing visible: its " + std::to_string(atlas.active_voxels) +
                      " active voxels are all zero";
    if (atlas.density_fixes.negative) why += " or negative (" + std::to_string(atlas.density_fixes.negative) + " negative)";
    return why + " under the material";
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

FrameResult Renderer::render(std::optional<int> frame, bool allow_empty) {
    FrameResult r;
    StageClock clock(r.stage_seconds);
    const std::string file = frame ? expandFramePattern(scene_.volume.path, *frame) : scene_.volume.path;

    LoadedVolume volume = clock("load", [&] { return loadVolume(file, scene_.volume); });
    r.warnings = volume.warnings;
    BrickAtlas atlas = clock("brick", [&] { return buildBrickAtlas(volume); });
    for (auto& line : sanitizeReport(atlas, volume)) r.warnings.push_back(line);
    PageTable pages = clock("classify", [&] {
        return buildPageTable(atlas.coords, classifyBricks(atlas, scene_.material));
    });
    r.bricks = pages.occupied;
    r.atlas_bytes = atlas.bytes();
    if (pages.empty()) {
        if (!allow_empty) throw InputError(emptyReason(volume, atlas));
        r.warnings.push_back(emptyReason(volume, atlas) + "; rendered as an empty frame");
        r.empty = true;
    }

    r.camera = scene_.camera ? *scene_.camera : frameActiveVoxels(volume, scene_.render);
    KernelInputs inputs = makeKernelInputs(scene_, r.camera, atlas, pages);
    r.image = clock("march", [&] { return backend_->march(inputs); });
    return r;
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
    StageClock clock(r.stage_seconds);
    ExrWriteReport written = clock("write", [&] { return writeExr(path, r.image, scene_.output, meta); });
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
