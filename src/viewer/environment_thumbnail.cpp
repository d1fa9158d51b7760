#include "viewer/environment_thumbnail.h"

#include <algorithm>
#include <cmath>

#include <imgui.h>

#include "core/error.h"
#include "grade/color_pipeline.h"
#include "grade/color_transformer.h"
#include "optics/environment_map.h"
#include "render/environment_lights.h"
#include "viewer/progressive_render.h"

namespace voxlux {
namespace {

constexpr int kMaxWidth = 256, kMaxHeight = 128;
constexpr float kMidGrey = 0.18f;

// The box-filtered average of `map` over out_w x out_h cells.
std::vector<glm::vec4> shrunk(const EnvironmentMap& map, int out_w, int out_h) {
    std::vector<glm::vec4> out(size_t(out_w) * out_h);
    for (int oy = 0; oy < out_h; ++oy)
        for (int ox = 0; ox < out_w; ++ox) {
            const int x0 = ox * map.width() / out_w, x1 = std::max(x0 + 1, (ox + 1) * map.width() / out_w);
            const int y0 = oy * map.height() / out_h, y1 = std::max(y0 + 1, (oy + 1) * map.height() / out_h);
            glm::vec3 sum(0.0f);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) sum += map.at({x, y});
            out[size_t(oy) * out_w + ox] = glm::vec4(sum / float((x1 - x0) * (y1 - y0)), 1.0f);
        }
    return out;
}

}  // namespace

EnvironmentThumbnail environmentThumbnail(const Scene& scene, size_t light) {
    // The cut as the march makes it, for a light that may be off or a scene that renders the reference.
    Scene lit = scene;
    lit.lights.at(light).enabled = true;
    lit.render.method = RenderMethod::March;
    lit = withEnvironmentLights(std::move(lit));
    const EnvironmentMap& map = *lit.lights[light].environment->loaded;

    EnvironmentThumbnail t;
    t.width = std::min(kMaxWidth, map.width());
    t.height = std::min(kMaxHeight, map.height());
    std::vector<glm::vec4> cells = shrunk(map, t.width, t.height);
    double mean = 0.0;
    for (const glm::vec4& c : cells) mean += environmentLuminance(glm::vec3(c));
    mean /= double(cells.size());
    const float exposure = mean > 0.0 ? float(kMidGrey / mean) : 0.0f;
    for (glm::vec4& c : cells) c = glm::vec4(glm::vec3(c) * exposure, 1.0f);
    const ColorPipeline pipeline = buildColorPipeline(scene.color, true);
    makeColorTransformer(Device::Cpu)->transformColors(pipeline.preview, cells, false);
    t.texels = opaqueTexels(cells);

    float total = 0.0f;
    for (const Light& l : lit.lights)
        if (l.from_environment == light && l.type == LightType::Directional) {
            const glm::ivec2 pixel = map.pixelOf(-glm::normalize(l.direction));
            const glm::vec2 uv = (glm::vec2(pixel) + 0.5f) / glm::vec2(map.width(), map.height());
            t.cut.push_back({uv, environmentLuminance(l.color)});
            total += t.cut.back().share;
        }
    for (auto& p : t.cut) p.share = total > 0.0f ? p.share / total : 0.0f;
    return t;
}

void EnvironmentThumbnailWidget::draw(const Scene& scene, size_t light) {
    const Light& l = scene.lights.at(light);
    const EnvironmentSettings& e = *l.environment;
    // What the picture shows: not the rotation, which leaves the file's layout as it is, nor the
    // intensity, which the exposure takes out (but for 0, which leaves a black map).
    const std::string key = std::to_string(l.intensity > 0.0f) + "|" + e.map + "|" + e.map_colorspace + "|" + std::to_string(e.median_cut_lights) + "|" +
                            std::to_string(int(e.remainder)) + "|" + std::to_string(l.color.x) + "," + std::to_string(l.color.y) +
                            "," + std::to_string(l.color.z) + "|" + scene.color.config + "|" + scene.color.working_space + "|" +
                            scene.color.display + "|" + scene.color.view;
    if (key != key_) {
        key_ = key;
        try {
            shown_ = environmentThumbnail(scene, light);
            error_.clear();
            texture_.upload(shown_.width, shown_.height, shown_.texels);
        } catch (const std::exception& failure) {   // the render names it too; the panel shows why there is no picture
            error_ = failure.what();
        }
    }
    if (!error_.empty()) {
        ImGui::TextWrapped("%s", error_.c_str());
        return;
    }
    const float width = ImGui::GetContentRegionAvail().x;
    const ImVec2 size(width, width * float(shown_.height) / float(std::max(shown_.width, 1)));
    const ImVec2 lo = ImGui::GetCursorScreenPos();
    ImGui::Image(texture_.imguiId(), size);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (const auto& p : shown_.cut) {
        const ImVec2 at(lo.x + p.uv.x * size.x, lo.y + p.uv.y * size.y);
        const float radius = 2.0f + 8.0f * std::sqrt(p.share);   // area by share
        draw->AddCircle(at, radius + 1.0f, IM_COL32(0, 0, 0, 200), 0, 2.0f);
        draw->AddCircle(at, radius, IM_COL32(255, 200, 60, 255), 0, 1.5f);
    }
    ImGui::TextDisabled("%zu median-cut lights; Shift + right drag in the view turns the map", shown_.cut.size());
}

}  // namespace voxlux
