// Grade stage: takes the march's premultiplied, scene-linear image in the working space to the
// output space, with the scene's grade (looks, CDLs, LUTs) applied to the beauty first, and makes
// the display-referred preview. The processors run on the render's device.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "grade/color_pipeline.h"
#include "grade/color_stages.h"
#include "grade/color_transformer.h"
#include "kernel/kernel_backend.h"
#include "render/march_stage.h"
#include "render/render_graph.h"

namespace voxlux {

// Grades `image` in place: the beauty through color.grade (unpremultiplied per
// color.unpremultiply) then color.output; the colour AOVs named in `aovs` (direct, ambient,
// indirect, emission) through color.output only, so they stay ungraded. Returns the preview's
// display-referred RGBA (the graded beauty over black through color.preview), or nothing when
// the pipeline has no preview.
std::vector<glm::vec4> gradeImage(RenderImage& image, const ColorPipeline& color, const std::vector<std::string>& aovs,
                                  ColorTransformer& transformer);

// The march's image graded (gradeImage), as a stage: it runs when the scene has grade steps,
// another output space or a preview, and a grade edit re-runs it without the march.
class GradeStage final : public Stage {
public:
    GradeStage(const MarchStage& march, const ColorTransformsStage& color) : march_(march), color_(color) {}
    std::string name() const override { return "grade"; }
    StageReads reads() const override { return {{"/output/aovs", "/render/backend"}, {"march", "color_transforms"}}; }
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
