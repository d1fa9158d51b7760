#include "render/environment_background.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "kernel/cpu_kernel_data.h"
#include "optics/environment_map.h"

namespace voxlux {

bool seesEnvironment(const KernelInputs& inputs) {
    return std::any_of(inputs.environments.begin(), inputs.environments.end(),
                       [](const KernelInputs::Environment& e) { return e.visible_to_camera; });
}

void addEnvironmentBackground(const KernelInputs& inputs, RenderImage& image) {
    if (!seesEnvironment(inputs)) return;
    kernel::CpuKernelData k = bindKernelData(inputs);
    const glm::ivec4 region = inputs.region;
    tbb::parallel_for(region.y, region.w, [&](int y) {
        for (int x = region.x; x < region.z; ++x) {
            glm::vec3 origin, dir, forward;
            k.vx_camera_ray(x, y, origin, dir, forward);
            if (k.vx_holdout_distance(x, y, dir, forward) < 1e30f) continue;
            const size_t pixel = size_t(y) * size_t(image.width) + size_t(x);
            kernel::VxPixel& px = image.pixels[pixel];
            const float behind = std::clamp(1.0f - px.rgba.w, 0.0f, 1.0f);
            for (const KernelInputs::Environment& env : inputs.environments) {
                if (!env.visible_to_camera) continue;
                const glm::vec3 light = env.map->filtered(dir) * behind;
                px.rgba += glm::vec4(light, 0.0f);
                if (size_t(env.group) < image.light_groups.size()) image.light_groups[size_t(env.group)].rgb[pixel] += light;
            }
            px.rgba.w = 1.0f;
        }
    });
}

}  // namespace voxlux
