#include "grade/grade_image.h"

#include <algorithm>

namespace voxlux {
namespace {

using PixelRgb = glm::vec3 kernel::VxPixel::*;

// Runs `processor` over one RGB plane of n values, `rgb(i)` the i-th (an AOV or a light group: no
// alpha, nothing to unpremultiply).
template <class Rgb>
void transformPlane(size_t n, Rgb rgb, const OCIO::ConstProcessorRcPtr& processor, ColorTransformer& transformer) {
    std::vector<glm::vec4> plane(n);
    for (size_t i = 0; i < n; ++i) plane[i] = glm::vec4(rgb(i), 1.0f);
    transformer.transformColors(processor, plane, false);
    for (size_t i = 0; i < n; ++i) rgb(i) = glm::vec3(plane[i]);
}

// The deep samples go through what the beauty does, each on its own: their composite is the
// graded beauty wherever the grade is linear (exposure, colour-space matrices).
void gradeDeepSamples(DeepSamples& deep, const ColorPipeline& color, ColorTransformer& transformer) {
    if (deep.samples.empty() || (color.grade->isNoOp() && color.output->isNoOp())) return;
    std::vector<glm::vec4> colors(deep.samples.size());
    for (size_t i = 0; i < colors.size(); ++i) colors[i] = glm::vec4(deep.samples[i].rgb, deep.samples[i].alpha);
    if (!color.grade->isNoOp()) transformer.transformColors(color.grade, colors, color.unpremultiply);
    if (!color.output->isNoOp()) transformer.transformColors(color.output, colors, color.unpremultiply);
    for (size_t i = 0; i < colors.size(); ++i) deep.samples[i].rgb = glm::vec3(colors[i]);
}

}  // namespace

std::vector<glm::vec4> gradeImage(RenderImage& image, const ColorPipeline& color, const std::vector<std::string>& aovs,
                                  ColorTransformer& transformer) {
    std::vector<glm::vec4> beauty(image.pixels.size());
    for (size_t i = 0; i < beauty.size(); ++i) beauty[i] = image.pixels[i].rgba;
    if (!color.grade->isNoOp()) transformer.transformColors(color.grade, beauty, color.unpremultiply);

    // The preview composites the graded beauty over black, which premultiplied colour already is.
    std::vector<glm::vec4> preview;
    if (color.preview) {
        preview = beauty;
        transformer.transformColors(color.preview, preview, false);
    }
    if (!color.output->isNoOp()) {
        transformer.transformColors(color.output, beauty, color.unpremultiply);
        const std::pair<const char*, PixelRgb> planes[] = {{"direct", &kernel::VxPixel::direct},
                                                           {"ambient", &kernel::VxPixel::ambient},
                                                           {"indirect", &kernel::VxPixel::indirect},
                                                           {"emission", &kernel::VxPixel::emission}};
        for (const auto& plane : planes) {
            const PixelRgb member = plane.second;   // a copy: Clang 14 captures no structured binding
            if (std::find(aovs.begin(), aovs.end(), plane.first) != aovs.end())
                transformPlane(image.pixels.size(), [&](size_t i) -> glm::vec3& { return image.pixels[i].*member; }, color.output, transformer);
        }
        for (LightGroupLayer& layer : image.light_groups)
            transformPlane(layer.rgb.size(), [&](size_t i) -> glm::vec3& { return layer.rgb[i]; }, color.output, transformer);
    }
    for (size_t i = 0; i < beauty.size(); ++i) image.pixels[i].rgba = beauty[i];
    gradeDeepSamples(image.deep, color, transformer);
    return preview;
}

}  // namespace voxlux
