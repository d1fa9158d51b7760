// The colour side of the render graph (OpenColorIO, docs/color.md), as two stages that run before
// any volume is read, so a bad config, space or look fails at once:
//  color_space       the config and the working space, with the CIE XYZ matrix that blackbody
//                    emission needs: what the march reads;
//  color_transforms  the grade, output and preview processors over them: what the grade and the
//                    EXR's colour metadata read. A grade edit re-runs this and the grade alone.
// Cost: parsing the config (milliseconds; the built-in one is embedded) and building processors.
#pragma once
#include <optional>

#include "grade/color_pipeline.h"
#include "graph/render_graph.h"

namespace voxlux {

class ColorSpaceStage final : public Stage {
public:
    std::string name() const override { return "color_space"; }
    StageReads reads() const override { return {{"/color/config", "/color/working_space", "/input/ocio", "/volumes/*/emission/*/kind"}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    const ColorPipeline& working() const { return *working_; }
    // CIE XYZ (D65) -> working space; identity when no source needs it.
    glm::mat3 xyzToWorking() const { return working_->xyz_to_working.value_or(glm::mat3(1.0f)); }

private:
    std::optional<ColorPipeline> working_;   // config and working space only
};

class ColorTransformsStage final : public Stage {
public:
    explicit ColorTransformsStage(const ColorSpaceStage& space) : space_(input(space)) {}
    std::string name() const override { return "color_transforms"; }
    StageReads reads() const override { return {{"/color", "/output/preview"}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    const ColorPipeline& pipeline() const { return *pipeline_; }

private:
    const ColorSpaceStage& space_;
    std::optional<ColorPipeline> pipeline_;
};

// Grade steps, another output space, or a preview: what makes the grade stage run.
bool needsGrade(const Scene& scene);

}  // namespace voxlux
