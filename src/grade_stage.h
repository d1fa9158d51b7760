// Grade stage: takes the march's premultiplied, scene-linear image in the working space to the
// output space, with the scene's grade (looks, CDLs, LUTs) applied to the beauty first, and makes
// the display-referred preview. The processors run on the render's backend.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "color_pipeline.h"
#include "kernel_backend.h"

namespace voxlux {

// Grades `image` in place: the beauty through color.grade (unpremultiplied per
// color.unpremultiply) then color.output; the colour AOVs named in `aovs` (direct, ambient,
// indirect, emission) through color.output only, so they stay ungraded. Returns the preview's
// display-referred RGBA (the graded beauty over black through color.preview), or nothing when
// the pipeline has no preview.
std::vector<glm::vec4> gradeImage(RenderImage& image, const ColorPipeline& color, const std::vector<std::string>& aovs,
                                  KernelBackend& backend);

}  // namespace voxlux
