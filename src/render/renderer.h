// Renders frames of a scene through the render graph (src/graph/render_graph.h): the stages below, each
// re-run only when what it reads changed, so a later frame or a scene edit recomputes only what it
// invalidates. The CLI, the study, the benchmarks and the tests all render through this.
//
//   color_space -> color_transforms ---------------------------------------------------.
//   load -> brick -> classify -> empty_check -------------------------------------------+
//       |                \-> light_grid -+-> sat -> light_cache --------------------------+-> march -> grade -> write
//       |                                 \-> illumination_grid -> propagation -> eye_pass -+
//        `-> camera --------------------------------------------------------------------'
//   (color_space also feeds illumination_grid, whose emission is in the working space, and the march.)
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "grade/color_stages.h"
#include "lighting/extinction_sat/extinction_sat_stages.h"
#include "render/grade_stage.h"
#include "kernel/kernel_backend.h"
#include "render/march_stage.h"
#include "lighting/propagation/propagation_stages.h"
#include "graph/render_graph.h"
#include "scene/scene.h"
#include "volume/volume_stages.h"
#include "render/write_stage.h"

namespace voxlux {

struct FrameResult {
    RenderImage image;                                      // graded when the grade ran
    Camera camera;                                          // as used (the scene's or the framing)
    std::vector<std::pair<std::string, double>> stage_seconds;   // the stages that ran, by graph name
    std::vector<StageReport> stages;                        // every stage this frame needed, ran or not
    std::vector<std::string> warnings;                      // recoverable oddities, one line each
    bool empty = false;                                     // nothing visible in this frame
    size_t atlas_bytes = 0;
    size_t bricks = 0;
    std::string path;                                       // the EXR written (renderToFile)
    std::vector<std::string> reused;                        // stages kept whole, then parts kept inside stages that ran
    std::optional<LightUpdate> light_update;                // what the propagation stage did (Kept when reused), if active
    std::vector<glm::vec4> preview;                         // display-referred RGBA, when output.preview is set
    std::string preview_path;                               // the PNG written (renderToFile)
    std::string deep_path;                                  // the deep EXR written (renderToFile, output.deep)
};

// The files renderToFile wrote, for a "wrote" line: "a.exr, a.deep.exr and a.png".
std::string writtenFilesText(const FrameResult& r);

// What keeps `scene` from being written: a missing output path (its message), or nothing.
std::optional<std::string> outputPathProblem(const Scene& scene);

class Renderer {
public:
    explicit Renderer(Scene scene);
    // The stages hold references to each other: a Renderer stays where it was made.
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    // Renders `volume` (grids made in memory) instead of reading files, on `backend` (not owned).
    Renderer(Scene scene, LoadedVolume volume, KernelBackend& backend);
    // Replaces the scene; the next render recomputes only what the change invalidates.
    void setScene(Scene scene);
    const Scene& scene() const { return scene_; }
    // Asked between stages while rendering (RenderGraph::run): the viewer cancels a render its
    // next edit makes stale. Renders then throw Cancelled.
    void setCancellation(std::function<bool()> cancelled) { cancelled_ = std::move(cancelled); }
    // Told the name of each stage as it starts to run: a sequence's progress bar shows it.
    void setStageStart(std::function<void(const std::string&)> starting) { stage_start_ = std::move(starting); }
    // A reference render whose sample count grows continues its image (MarchStage::keepReferenceSums).
    void keepReferenceSums(bool keep) { march_.keepReferenceSums(keep); }
    // Keeps the grids and bricks of frames rendered before within `bytes`, so that coming back
    // to a frame reads and densifies nothing (RenderGraph::setCacheBudget): a viewer's timeline.
    void setCacheBudget(size_t bytes) { graph_.setCacheBudget(bytes); }
    const RenderGraph& graph() const { return graph_; }
    std::string backendName() { return backend().name(); }

    // Renders one frame (`frame` expands a #### volume path). An empty frame throws InputError
    // unless `allow_empty`, in which case it renders transparent and says so in the warnings.
    FrameResult render(std::optional<int> frame, bool allow_empty);

    // Runs every stage but the march, grade and write (no image): brings the lighting up to date
    // after an edit, as a light-edit replay does between frames.
    FrameResult prepare(std::optional<int> frame, bool allow_empty);

    // Renders and writes the EXR for `frame` to the scene's output path (#### expanded); throws
    // outputPathProblem's message when the scene has none.
    FrameResult renderToFile(std::optional<int> frame, bool allow_empty);

    // What the march read last: the illumination volume (with the eye pass's indirect light when
    // it ran), or null without propagation; and the light cache, or null.
    const IlluminationVolume* illumination() const;
    const LightCache* lightCache() const;

    // The render document for `frame`: the scene as sceneToJson writes it, plus /input (the
    // frame's file and its size and time, the frame number, $OCIO and allow_empty).
    nlohmann::json document(std::optional<int> frame, bool allow_empty) const;

private:
    FrameResult runGraph(std::optional<int> frame, bool allow_empty, const std::vector<std::string>& targets);
    KernelBackend& backend();   // the scene's, made on first use (--explain needs none)

    Scene scene_;
    std::function<bool()> cancelled_;
    std::function<void(const std::string&)> stage_start_;
    std::unique_ptr<KernelBackend> owned_backend_;
    KernelBackend* backend_ = nullptr;
    ColorSpaceStage color_space_;
    ColorTransformsStage color_transforms_{color_space_};
    LoadStage load_;
    Transfer2dStage transfer_2d_{load_};
    BrickStage brick_{transfer_2d_};
    ClassifyStage classify_{transfer_2d_, brick_};
    EmptyFrameStage empty_check_{classify_};
    CameraStage camera_{transfer_2d_};
    LightGridStage light_grid_{brick_, classify_, {{"the SAT", lightCacheRuns}, {"the illumination volume", illuminationVolumeRuns}}};
    SatStage sat_{brick_, classify_, light_grid_};
    LightCacheStage light_cache_{brick_, classify_, sat_};
    IlluminationGridStage illumination_grid_{[this] { return color_space_.xyzToWorking(); }, brick_, classify_, light_grid_};
    PropagationStage propagation_{brick_, classify_, illumination_grid_};
    EyePassStage eye_pass_{brick_, classify_, camera_, illumination_grid_, propagation_};
    MarchStage march_{color_space_, brick_, classify_, camera_, {light_cache_, propagation_, eye_pass_}};
    GradeStage grade_{march_, color_transforms_};
    WriteStage write_{grade_, camera_, color_transforms_};
    RenderGraph graph_{{&color_space_, &color_transforms_, &load_, &transfer_2d_, &brick_, &classify_, &empty_check_, &camera_,
                         &light_grid_, &sat_, &light_cache_, &illumination_grid_, &propagation_, &eye_pass_, &march_,
                         &grade_, &write_}};
};

}  // namespace voxlux
