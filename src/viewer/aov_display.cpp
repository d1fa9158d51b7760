#include "viewer/aov_display.h"

#include <algorithm>
#include <cmath>

#include "core/json_reader.h"
#include "grade/color_transformer.h"
#include "scene/scene_json.h"

namespace voxlux {

const std::vector<uint8_t>& AovDisplay::texels(const ViewFrame& frame, const std::string& aov, const ColorSettings& color) {
    if (aov == "beauty") return frame.display_texels;
    const std::vector<kernel::VxPixel>& px = frame.image.pixels;
    std::vector<glm::vec4> out(px.size());
    if (aov == "transmittance" || aov == "depth") {
        float top = 0.0f;
        if (aov == "depth")
            for (const auto& p : px)
                if (std::isfinite(p.depth)) top = std::max(top, p.depth);
        for (size_t i = 0; i < px.size(); ++i) {
            const float v = aov == "depth" ? (top > 0.0f ? px[i].depth / top : 0.0f) : px[i].transmittance;
            out[i] = glm::vec4(glm::vec3(v), 1.0f);
        }
        return texels_ = opaqueTexels(out);
    }
    for (size_t i = 0; i < px.size(); ++i) {
        const glm::vec3 c = aov == "direct" ? px[i].direct : aov == "indirect" ? px[i].indirect : aov == "ambient" ? px[i].ambient : px[i].emission;
        out[i] = glm::vec4(c, 1.0f);
    }
    Scene probe;
    probe.color = color;
    const std::string key = jsonText(sceneToJson(probe)["color"]);
    if (key != pipeline_key_) {
        pipeline_ = buildColorPipeline(color, true);
        pipeline_key_ = key;
    }
    makeColorTransformer(Device::Cpu)->transformColors(pipeline_.preview, out, false);
    return texels_ = opaqueTexels(out);
}

}  // namespace voxlux
