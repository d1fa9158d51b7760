// Runs the render plan for one frame: load -> brick -> classify -> light cache / illumination ->
// march -> write,
// timing each stage and keeping what a later frame or scene edit can reuse. The CLI, the benchmark and the tests all render through this.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "brick_atlas.h"
#include "color_pipeline.h"
#include "illumination_stage.h"
#include "kernel_backend.h"
#include "light_stage.h"
#include "render_plan.h"
#include "scene.h"
#include "vdb_loader.h"

namespace voxlux {

struct FrameResult {
    RenderImage image;
    Camera camera;                                          // as used (the scene's or the framing)
    std::vector<std::pair<std::string, double>> stage_seconds;
    std::vector<std::string> warnings;                      // recoverable oddities, one line each
    bool empty = false;                                     // nothing visible in this frame
    size_t atlas_bytes = 0;
    size_t bricks = 0;
    std::string path;                                       // the EXR written (renderToFile)
    std::vector<std::string> reused;                        // stages and passes kept from before
    std::optional<LightUpdate> light_update;                // what the illumination stage did, if it ran
    std::vector<glm::vec4> preview;                         // display-referred RGBA, when output.preview is set
    std::string preview_path;                               // the PNG written (renderToFile)
};

// Camera framing the active voxels of the density grid: what a scene without a camera renders
// and what `voxlux scene` writes out.
Camera frameActiveVoxels(const LoadedVolume& volume, const RenderSettings& render);
Camera frameVolumeCamera(const std::string& file, const Scene& scene);

class Renderer {
public:
    explicit Renderer(Scene scene);
    // Replaces the scene; the next render recomputes only what the change invalidates.
    void setScene(Scene scene);
    const std::vector<PlannedStage>& plan() const { return plan_; }
    std::string backendName() const { return backend_->name(); }
    // The illumination volume as the last frame left it (for the viewer's display and tests).
    const IlluminationStage& illumination() const { return illumination_; }
    // The scene's OCIO config and processors; built on first use, rebuilt when color changes.
    const ColorPipeline& color();

    // Renders one frame (`frame` expands a #### volume path). An empty frame throws InputError
    // unless `allow_empty`, in which case it renders transparent and says so in the warnings.
    FrameResult render(std::optional<int> frame, bool allow_empty);

    // Runs every stage but the march (no image): brings the cached stages up to date after an
    // edit, as a light-edit replay does between frames.
    FrameResult prepare(std::optional<int> frame, bool allow_empty);

    // Renders and writes the EXR for `frame` to the scene's output path (#### expanded).
    FrameResult renderToFile(std::optional<int> frame, bool allow_empty);

private:
    std::string volumeKey(const std::string& file) const;
    KernelInputs runStages(std::optional<int> frame, bool allow_empty, FrameResult& r);
    glm::mat3 xyzToWorking();

    Scene scene_;
    std::vector<PlannedStage> plan_;
    std::string color_key_;                                 // the color settings and $OCIO color_ was built for
    std::optional<ColorPipeline> color_;
    std::unique_ptr<KernelBackend> backend_;
    std::string volume_key_;                                // of the volume below; "" = none
    std::unique_ptr<LoadedVolume> volume_;
    std::unique_ptr<BrickAtlas> atlas_;
    PageTable pages_;                                       // this frame's classified bricks (the inputs point here)
    LightStage light_;
    IlluminationStage illumination_;
};

// FNV-1a of the scene as rendered (canonical JSON), hex; written into the EXR metadata.
std::string sceneHash(const Scene& scene);

}  // namespace voxlux
