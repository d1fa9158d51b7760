#include "render/holdout_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/frame_pattern.h"
#include "io/exr_reader.h"
#include "kernel/cpu_kernel_data.h"
#include "render/mesh_rays.h"
#include "scene/camera.h"
#include "scene/scene_json.h"
#include "volume/holdout_mesh_stage.h"
#include "volume/volume_stages.h"

namespace voxlux {

StageReads HoldoutStage::reads() const {
    return {{"/holdouts", "/input/holdout_files", "/input/holdout_placements", "/input/frame", "/render/resolution"}};
}

StageActivity HoldoutStage::activity(const Scene& s) const {
    if (s.holdouts.empty()) return {false, "skipped: no holdouts"};
    const size_t meshes = size_t(std::count_if(s.holdouts.begin(), s.holdouts.end(), [](const Holdout& h) { return !h.mesh.empty(); }));
    const size_t images = s.holdouts.size() - meshes;
    std::string what;
    if (images) what = std::to_string(images) + (images == 1 ? " depth image" : " depth images");
    if (meshes) what += (images ? " and " : "") + std::to_string(meshes) + (meshes == 1 ? " mesh (a ray a pixel)" : " meshes (a ray a pixel)");
    return {true, "camera rays stop at the nearest surface of " + what};
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
    std::vector<const TriangleMesh*> meshes;
    std::vector<glm::mat4> placements;
    for (size_t i = 0; i < scene.holdouts.size(); ++i) {
        const Holdout& h = scene.holdouts[i];
        if (!h.mesh.empty()) {
            meshes.push_back(meshes_.mesh(i));
            placements.push_back(matrixFromJson(run.scene.value("/input/holdout_placements/meshes/" + std::to_string(i))));
            continue;
        }
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
    if (!meshes.empty()) {
        const MeshRays rays(meshes, placements);
        k.P.width = width;
        k.P.height = height;
        const glm::mat4 to_world = cameraToWorld(camera_.camera());
        tbb::parallel_for(0, height, [&](int y) {
            for (int x = 0; x < width; ++x) {
                glm::vec3 origin, dir, forward;
                k.vx_camera_ray_of(to_world, x, y, origin, dir, forward);
                const float z = rays.nearestHit(origin, dir) * glm::dot(dir, forward);
                float& nearest = depth[size_t(y) * width + size_t(x)];
                if (z > 0.0f && z < nearest) nearest = z;
            }
        });
    }
    depth_ = std::move(depth);
}

}  // namespace voxlux
