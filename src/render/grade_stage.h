// Grade stage: the march's image graded (grade/grade_image.h) on the render's device, re-run by a
// grade edit without the march. It lives with the march because it reads the march's image.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "grade/color_stages.h"
#include "grade/color_transformer.h"
#include "grade/grade_image.h"
#include "graph/render_graph.h"
#include "kernel/kernel_backend.h"
#include "render/march_stage.h"

namespace voxlux {

// The march's image exposed and graded (gradeImage), as a stage: it runs when the scene has an
// exposure, grade steps, another output space or a preview, and a grade edit re-runs it without the march.
class GradeStage final : public Stage {
public:
    GradeStage(const MarchStage& march, const ColorTransformsStage& color) : march_(input(march)), color_(input(color)) {}
    std::string name() const override { return "grade"; }
    StageReads reads() const override { return {{"/output/aovs", "/render/backend", "/render/exposure"}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void release() override;
    // The graded image, or the march's when the grade does not run.
    const RenderImage& result() const { return image_.pixels.empty() ? march_.image() : image_; }
    const std::vector<glm::vec4>& preview() const { return preview_; }   // display-referred RGBA, or empty

private:
    const MarchStage& march_;
    const ColorTransformsStage& color_;
    OnDevice<ColorTransformer> transformer_{makeColorTransformer};
    RenderImage image_;
    std::vector<glm::vec4> preview_;
};

}  // namespace voxlux
