#include "render/holdout_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/frame_pattern.h"
#include "io/exr_reader.h"
#include "kernel/cpu_kernel_data.h"
#include "volume/volume_stages.h"

namespace voxlux {

StageReads HoldoutStage::reads() const { return {{"/holdouts", "/input/holdout_files", "/input/frame", "/render/resolution"}}; }

StageActivity HoldoutStage::activity(const Scene& s) const {
    if (s.holdouts.empty()) return {false, "skipped: no holdouts"};
    const size_t n = s.holdouts.size();
    return {true, "camera rays stop at the nearest surface of " + std::to_string(n) + (n == 1 ? " depth image" : " depth images")};
}

void HoldoutStage::run(StageRun& run) {
    const Scene& scene = run.scene({"/holdouts", "/render/resolution"});
    const nlohmann::json& frame = run.scene.value("/input/frame");
    const int width = scene.render.width, height = scene.render.height;
    const float none = std::numeric_limits<float>::max();
    std::vector<float> depth(size_t(width) * height, none);
    // A ray distance d along pixel (x, y)'s ray is camera-space Z = d * cos, the cosine between
    // the pixel's ray and the camera's forward axis: the kernel's own camera ray
    // (vx_camera_ray_of), of a camera at the image's resolution.
    kernel::CpuKernelData k;
    k.P.tan_half_fov = std::tan(glm::radians(camera_.camera().fov) * 0.5f);
    k.P.aspect = float(width) / float(height);
    for (const Holdout& h : scene.holdouts) {
        const std::string path = frame.is_number() ? expandFramePattern(h.depth, frame.get<int>()) : h.depth;
        const ExrChannel image = readExrChannel(path, h.channel);
        // The render's resolution, or a whole multiple of it (the viewer's coarse levels): then each
        // render pixel takes the nearest surface of its block of image pixels.
        const int f = image.width / width;
        if (f < 1 || image.width != f * width || image.height != f * height)
            throw InputError(path + ": is " + std::to_string(image.width) + "x" + std::to_string(image.height) + ", the render " +
                             std::to_string(width) + "x" + std::to_string(height) +
                             ": a depth holdout is read pixel for pixel (or in whole blocks of pixels)");
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                float z = image.values[size_t(y) * image.width + x];
                // No surface: the background's 0, infinity or NaN (renderers write any of them).
                if (!(z > 0.0f) || !std::isfinite(z)) continue;
                if (h.ray_distance) {
                    k.P.width = image.width;
                    k.P.height = image.height;
                    glm::vec3 origin, dir, forward;
                    k.vx_camera_ray_of(glm::mat4(1.0f), x, y, origin, dir, forward);
                    z *= glm::dot(dir, forward);
                }
                float& nearest = depth[size_t(y / f) * width + size_t(x / f)];
                nearest = std::min(nearest, z);
            }
    }
    depth_ = std::move(depth);
}

}  // namespace voxlux
