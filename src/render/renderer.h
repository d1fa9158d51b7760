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

#include <glm/glm.hpp>

#include "graph/render_graph.h"
#include "kernel/kernel_backend.h"
#include "lighting/light_update.h"
#include "lighting/march_lighting.h"
#include "scene/scene.h"


namespace voxlux {

struct LoadedVolume;

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
    // The scene's disabled volumes are left out (withEnabledVolumes): scene() is the scene as it renders.
    explicit Renderer(Scene scene);
    ~Renderer();
    // The stages hold references to each other: a Renderer stays where it was made.
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    // Renders `volume` (grids made in memory: the first enabled volume's) instead of reading files,
    // on `backend` (not owned).
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
    void keepReferenceSums(bool keep);
    // Keeps the grids and bricks of frames rendered before within `bytes`, so that coming back
    // to a frame reads and densifies nothing (RenderGraph::setCacheBudget): a viewer's timeline.
    void setCacheBudget(size_t bytes) { graph_.setCacheBudget(bytes); }
    const RenderGraph& graph() const { return graph_; }
    std::string backendName() { return backend().name(); }

    // Renders one frame (`frame` expands a #### volume path). An empty frame throws InputError
    // unless `allow_empty`, in which case it renders transparent and says so in the warnings.
    FrameResult render(std::optional<int> frame, bool allow_empty);
    // Of the last frame rendered, per pixel: the nearest holdout's camera-space Z, the largest
    // float where none stands (empty without holdouts). The viewer draws the CG's silhouette there.
    const std::vector<float>& holdoutDepth() const;

    // Runs every stage but the march, grade and write (no image): brings the lighting up to date
    // after an edit, as a light-edit replay does between frames.
    FrameResult prepare(std::optional<int> frame, bool allow_empty);

    // Renders and writes the EXR for `frame` to the scene's output path (#### expanded); throws
    // outputPathProblem's message when the scene has none.
    FrameResult renderToFile(std::optional<int> frame, bool allow_empty);

    // What the march read last of type `Output` (a lighting method's: IlluminationVolume, with the
    // eye pass's indirect light when it ran; LightCache), the later of its lighting stages over the
    // earlier, or null when none holds one.
    template <class Output>
    const Output* lightingOutput() const {
        const Output* out = nullptr;
        for (const MarchLightingStage* stage : lightingStages())
            if (const auto* typed = dynamic_cast<const MarchLightingStageOf<Output>*>(stage); typed && typed->marchOutput())
                out = typed->marchOutput();
        return out;
    }
    const std::vector<const MarchLightingStage*>& lightingStages() const;

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
    // The stages, each holding references to the ones it reads (renderer.cpp), and the graph
    // over them.
    struct Stages;
    std::unique_ptr<Stages> stages_;
    RenderGraph graph_;
};

}  // namespace voxlux
