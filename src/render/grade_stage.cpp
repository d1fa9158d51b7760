#include "render/grade_stage.h"

#include <cmath>
#include <filesystem>
#include <limits>

namespace voxlux {

// What the grade stage does, or why it is skipped. Names are as the scene gives them; the
// color_transforms stage resolves them (and reports missing ones) before any volume is read.
StageActivity GradeStage::activity(const Scene& s) const {
    const ColorSettings& c = s.color;
    const std::string working = c.working_space.empty() ? "the scene_linear role" : c.working_space;
    if (!needsGrade(s)) return {false, "skipped: no grade, output in the working space (" + working + "), no preview"};
    std::string steps;
    for (const auto& g : c.grade) {
        std::string step = g.kind == GradeKind::Look  ? "look '" + g.look + "'"
                           : g.kind == GradeKind::Cdl ? std::string("CDL")
                                                      : "'" + std::filesystem::path(g.file).filename().string() + "'";
        if (!g.space.empty()) step += " in " + g.space;
        if (g.inverse) step += " (inverse)";
        steps += steps.empty() ? "grade " : ", ";
        steps += step;
    }
    std::vector<std::string> parts;
    if (s.render.exposure != 0.0f) parts.push_back("exposure " + std::to_string(s.render.exposure) + " stops");
    if (!steps.empty()) parts.push_back(steps + (c.unpremultiply ? " on unpremultiplied colour" : ""));
    if (!c.output_space.empty() && c.output_space != c.working_space) parts.push_back(working + " -> " + c.output_space);
    if (!s.output.preview.empty())
        parts.push_back("preview through " + (c.display.empty() ? std::string("the default display") : "'" + c.display + "'") +
                        (c.view.empty() ? "" : " / '" + c.view + "'"));
    std::string out;
    for (const auto& p : parts) out += (out.empty() ? "" : "; ") + p;
    return {true, out};
}

namespace {

// Exposure scales light, so the beauty's colour, the light AOVs and light groups, the deep samples'
// colour and the variance (by the square); alpha, transmittance and depth stay. Results above the float maximum
// stay at it.
void expose(RenderImage& image, float stops) {
    if (stops == 0.0f) return;
    const float gain = std::exp2(stops);
    const auto scale = [](glm::vec3 v, float g) { return glm::min(v * g, glm::vec3(std::numeric_limits<float>::max())); };
    for (kernel::VxPixel& p : image.pixels) {
        p.rgba = glm::vec4(scale(glm::vec3(p.rgba), gain), p.rgba.w);
        p.direct = scale(p.direct, gain);
        p.ambient = scale(p.ambient, gain);
        p.emission = scale(p.emission, gain);
        p.indirect = scale(p.indirect, gain);
        p.variance = std::min(p.variance * gain * gain, std::numeric_limits<float>::max());
    }
    for (kernel::VxDeepSample& s : image.deep.samples) s.rgb = scale(s.rgb, gain);
    for (LightGroupLayer& layer : image.light_groups)
        for (glm::vec3& c : layer.rgb) c = scale(c, gain);
}

}  // namespace

void GradeStage::run(StageRun& run) {
    image_ = march_.image();
    const Scene& scene = run.scene({"/render/exposure", "/output/aovs"});
    expose(image_, scene.render.exposure);
    std::vector<std::string> aovs;
    for (const auto& aov : scene.output.aovs) aovs.push_back(aov.name);
    preview_ = gradeImage(image_, color_.pipeline(), aovs, transformer_.on(run.backend));
}

void GradeStage::release() {
    image_ = RenderImage{};
    preview_.clear();
}

}  // namespace voxlux
