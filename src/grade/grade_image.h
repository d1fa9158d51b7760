// Grading a rendered image: the march's premultiplied, scene-linear image in the working space
// taken to the output space, with the scene's grade (looks, CDLs, LUTs) applied to the beauty
// first, and the display-referred preview made from it. The processors run on the transformer's
// device; the cost is one pass over the pixels per processor.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "grade/color_pipeline.h"
#include "grade/color_transformer.h"
#include "kernel/kernel_backend.h"

namespace voxlux {

// Grades `image` in place: the beauty through color.grade (unpremultiplied per
// color.unpremultiply) then color.output; the colour AOVs named in `aovs` (direct, ambient,
// indirect, emission) and the light groups through color.output only, so they stay ungraded (they
// sum to the beauty before its grade). Returns the preview's
// display-referred RGBA (the graded beauty over black through color.preview), or nothing when
// the pipeline has no preview. Deep samples go through the beauty's processors, each on its own.
std::vector<glm::vec4> gradeImage(RenderImage& image, const ColorPipeline& color, const std::vector<std::string>& aovs,
                                  ColorTransformer& transformer);

}  // namespace voxlux
