// The last stage of the render graph: the EXR (the graded image when the grade ran, else the
// march's) with its AOVs and metadata, and the 8-bit preview PNG when output.preview asks for
// one, both written to a temporary file and renamed. It reads the whole render document, since
// the EXR carries the scene's hash. Cost: compression, tens of milliseconds at 512^2.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "grade/color_stages.h"
#include "render/grade_stage.h"
#include "render/march_stage.h"
#include "render/volume_coverage.h"
#include "graph/render_graph.h"
#include "volume/volume_stages.h"

namespace voxlux {

class WriteStage final : public Stage {
public:
    WriteStage(const GradeStage& grade, const CameraStage& camera, const ColorTransformsStage& color, const CoverageStage& coverage)
        : grade_(input(grade)), camera_(input(camera)), color_(input(color)), coverage_(input(coverage)) {}
    std::string name() const override { return "write"; }
    StageReads reads() const override { return {{""}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    const std::string& path() const { return path_; }                 // the EXR written
    const std::string& previewPath() const { return preview_path_; }  // the PNG written, or ""
    const std::string& deepPath() const { return deep_path_; }        // the deep EXR written, or ""

private:
    const GradeStage& grade_;
    const CameraStage& camera_;
    const ColorTransformsStage& color_;
    const CoverageStage& coverage_;
    std::string path_, preview_path_, deep_path_;
};

// The files a frame writes: the EXR, then the preview and the deep EXR when the scene asks for them.
std::vector<std::string> frameOutputPaths(const Scene& scene, std::optional<int> frame);

// FNV-1a of what decides a frame's pixels, hex: the scene as its file says (canonical JSON, with
// its input paths absolute; its disabled volumes and what the renderer derives left out), less
// volume.frames and the output paths, so that a frame rendered alone, in a farm's chunk or in the
// whole sequence carries the same hash. Written into the EXR metadata;
// `--resume` and `farm collect` compare it.
std::string sceneHash(const Scene& scene);

}  // namespace voxlux
