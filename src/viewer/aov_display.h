// The viewport's image for the AOV picked: the beauty as the grade stage's preview made it (the
// scene's display and view through OCIO), a colour AOV through the same display transform, and
// transmittance or depth (scaled by its largest value) as grey. Costs one OCIO CPU pass over the
// pixels for a colour AOV, a copy otherwise.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "grade/color_pipeline.h"
#include "viewer/progressive_render.h"

namespace voxlux {

class AovDisplay {
public:
    // Display-referred RGBA of `aov` (one of kViewAovs) in `frame`, under the colour settings `color`.
    std::vector<glm::vec4> show(const ViewFrame& frame, const std::string& aov, const ColorSettings& color);

private:
    std::string pipeline_key_;   // the colour settings the pipeline was built for
    ColorPipeline pipeline_;
};

}  // namespace voxlux
