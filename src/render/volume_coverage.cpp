#include "render/volume_coverage.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "kernel/cpu_kernel_data.h"
#include "kernel/medium_inputs.h"

namespace voxlux {

CoveragePlanes volumeCoverage(const KernelInputs& in, const std::vector<int>& scene_volume, const std::vector<std::string>& names) {
    kernel::CpuKernelData k = bindKernelData(in);
    const auto& P = k.P;
    CoveragePlanes out{names, std::vector<std::vector<float>>(names.size(), std::vector<float>(size_t(P.width) * P.height, 0.0f))};
    const glm::ivec4 region = in.region;
    tbb::parallel_for(region.y, region.w, [&](int y) {
        std::vector<float> pixel(names.size());
        for (int x = region.x; x < region.z; ++x) {
            std::fill(pixel.begin(), pixel.end(), 0.0f);
            // The pixel's rays of vx_render_pixel, their mean.
            for (int ray = 0; ray < P.time_samples; ++ray) {
                glm::vec3 origin, dir, forward;
                const float time = k.vx_pixel_ray(x, y, ray, origin, dir, forward);
                float t0 = 0.0f, t1 = 1e30f;
                if (!k.vx_volumes_clip(origin, dir, t0, t1)) continue;
                // The samples and transmittance of vx_march_volumes, up to a holdout.
                const float dt = P.step, share = 1.0f / float(P.time_samples);
                const float t_cut = k.vx_holdout_distance(x, y, dir, forward);
                t1 = std::min(t1, t_cut + 0.5f * dt);
                float tau = 0.0f, T = 1.0f;
                kernel::CpuKernelData::VxMedium m;
                for (int s = k.vx_first_sample(t0, 1.0f / dt); T > P.transmittance_cutoff && k.vx_volumes_sample(origin, dir, dt, t1, false, time, VX_ALL_LINKS, s, m); ++s) {
                    const glm::vec3 at = origin + dir * ((float(s) + 0.5f) * dt);
                    const float cut = k.vx_cut_share(s, dt, t_cut);
                    if (m.sigma_camera <= 0.0f) continue;
                    tau += m.sigma_camera * cut * dt;
                    const float T_next = k.vx_exp(-tau);
                    const float absorbed = T - T_next;
                    T = T_next;
                    if (m.sigma_visible <= 0.0f) continue;
                    for (int v = 0; v < P.volume_count; ++v) {
                        const kernel::VxVolume V = k.vx_placed_volume(v);
                        if (V.role != VX_ROLE_VISIBLE) continue;
                        bool in_box = false;
                        const float sigma = k.vx_volume_extinction(V, at, time, in_box);
                        if (sigma > 0.0f) pixel[size_t(scene_volume[size_t(v)])] += share * absorbed * (sigma / m.sigma_camera);   // both cut alike
                    }
                }
            }
            for (size_t v = 0; v < names.size(); ++v) out.planes[v][size_t(y) * P.width + x] = pixel[v];
        }
    });
    return out;
}

bool wantsCoverage(const Scene& scene) {
    return std::any_of(scene.output.aovs.begin(), scene.output.aovs.end(), [](const AovSpec& a) { return a.name == "coverage"; });
}

StageReads CoverageStage::reads() const {
    return {withPlacementKeys({"/output/aovs", "/volumes/*/name", "/volumes/*/material", "/render/resolution", "/render/step",
                               "/render/transmittance_cutoff", "/render/filter", "/render/region", "/render/motion_blur", "/input/light_links/sets"})};
}

StageActivity CoverageStage::activity(const Scene& s) const {
    if (!wantsCoverage(s)) return {false, "skipped: output.aovs has no coverage"};
    if (!rendersAsSeveral(s)) return {false, "skipped: one visible volume, whose coverage is the alpha"};
    return {true, "each volume's share of the alpha, " + std::to_string(s.volumes.size()) + " planes (extinction only, on the CPU)"};
}

void CoverageStage::run(StageRun& run) {
    const Scene& scene = run.scene(reads().keys);
    MarchSources sources;
    sources.camera = &camera_.camera();
    sources.holdout = &holdouts_.depth();
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame(), kXyzD65ToAcescg, sources);
    std::vector<int> scene_volume;
    std::vector<std::string> names;
    for (size_t v = 0; v < scene.volumes.size(); ++v) {
        // A mesh holdout's cells (the last volumes) have no channel: they are the CG's, never seen.
        if (!scene.volumes[v].holdout_mesh) names.push_back(scene.volumes[v].name);
        scene_volume.insert(scene_volume.end(), std::max<size_t>(1, scene.volumes[v].instances.size()), int(v));
    }
    planes_ = volumeCoverage(inputs, scene_volume, names);
}

}  // namespace voxlux
