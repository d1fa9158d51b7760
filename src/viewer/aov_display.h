// The viewport's texels for the AOV picked: the beauty as the grade stage's preview made it (the
// scene's display and view through OCIO; the worker made its texels), a colour AOV through the same
// display transform, and transmittance or depth (scaled by its largest value) as grey. Costs one
// OCIO CPU pass over the pixels for a colour AOV, nothing for the beauty.
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
    // The 8-bit RGBA texels (opaqueTexels) of `aov` (one of kViewAovs) in `frame`, under the colour
    // settings `color`; valid until the next call.
    const std::vector<uint8_t>& texels(const ViewFrame& frame, const std::string& aov, const ColorSettings& color);

private:
    std::vector<uint8_t> texels_;   // of the last AOV other than the beauty
    std::string pipeline_key_;   // the colour settings the pipeline was built for
    ColorPipeline pipeline_;
};

}  // namespace voxlux
