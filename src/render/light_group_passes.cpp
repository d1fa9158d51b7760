#include "render/light_group_passes.h"

#include <algorithm>

namespace voxlux {

kernel::VxParams lightGroupParams(const KernelInputs& in, int layer, int groups) {
    kernel::VxParams P = in.params;
    const bool emitted = layer == groups;
    P.light_group = layer;   // the emitted light's pass: no light is in it
    P.ambient = emitted ? glm::vec3(0.0f) : in.group_ambient[size_t(layer)];
    P.has_ambient = glm::any(glm::greaterThan(P.ambient, glm::vec3(0.0f))) ? 1 : 0;
    if (!emitted) P.emission_sources = 0;
    P.local_light_count = int(std::count_if(in.lights.begin(), in.lights.end(), [&](const kernel::VxLight& l) {
        return l.group == layer && l.type != VX_LIGHT_DIRECTIONAL;
    }));
    return P;
}

RenderImage marchLightGroups(KernelBackend& backend, const KernelInputs& inputs, const std::vector<std::string>& groups, int passes) {
    const int layers = int(groups.size()) + 1;
    std::vector<RenderImage> marched;
    for (int layer = 0; layer < passes; ++layer) {
        KernelInputs pass = inputs;
        pass.params = lightGroupParams(inputs, layer, int(groups.size()));
        marched.push_back(backend.march(pass));
    }
    RenderImage image = marched.front();   // alpha, transmittance and depth: the medium's, the same in every pass
    const size_t n = image.pixels.size();
    for (int layer = 0; layer < layers; ++layer) {
        LightGroupLayer l{layer < int(groups.size()) ? groups[size_t(layer)] : kEmissionLayer, std::vector<glm::vec3>(n, glm::vec3(0.0f))};
        if (layer < passes)
            for (size_t i = 0; i < n; ++i) l.rgb[i] = glm::vec3(marched[size_t(layer)].pixels[i].rgba);
        image.light_groups.push_back(std::move(l));
    }
    for (size_t i = 0; i < n; ++i) {
        kernel::VxPixel& px = image.pixels[i];
        glm::vec3 beauty(0.0f);
        for (int p = 1; p < passes; ++p) {
            const kernel::VxPixel& q = marched[size_t(p)].pixels[i];
            px.direct = kernel::vx_radiance_add(px.direct, q.direct);
            px.ambient = kernel::vx_radiance_add(px.ambient, q.ambient);
            px.indirect = kernel::vx_radiance_add(px.indirect, q.indirect);
            px.emission = kernel::vx_radiance_add(px.emission, q.emission);
            px.samples += q.samples;
        }
        for (const LightGroupLayer& l : image.light_groups) beauty = kernel::vx_radiance_add(beauty, l.rgb[i]);
        px.rgba = glm::vec4(beauty, px.rgba.w);
    }
    return image;
}

}  // namespace voxlux
