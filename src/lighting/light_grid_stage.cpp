#include "lighting/light_grid_stage.h"

#include <climits>

#include "core/error.h"
#include "kernel/medium_inputs.h"
#include "volume/volume_stages.h"

namespace voxlux {

StageReads LightGridStage::reads() const {
    return {withPlacementKeys({"/volumes/*/path", "/volumes/*/material", "/effects/light_resolution", "/effects/light_memory_mb", "/input/light_links/sets"})};
}

StageActivity LightGridStage::activity(const Scene& s) const {
    std::string readers;
    for (const LightGridReader& r : readers_)
        if (r.runs(s)) readers += (readers.empty() ? "" : " and ") + r.name;
    if (readers.empty()) {
        if (s.render.method == RenderMethod::Reference) return {false, kReferenceComputesAllLight};
        return {false, "skipped: no lighting method in the scene reads a light grid"};
    }
    if (rendersAsSeveral(s))
        return {true, "the " + std::to_string(placedVolumeCount(s)) + " volumes' extinction resampled into a " + std::to_string(s.effects.light_resolution) +
                          "-cell light grid over their shared box, for " + readers};
    return {true, "extinction box-filtered into a " + std::to_string(s.effects.light_resolution) +
                      "-cell light grid over the occupied bricks, for " + readers};
}

void LightGridStage::run(StageRun& run) {
    const Scene& scene = run.scene({"/effects/light_resolution", "/effects/light_memory_mb", "/volumes/*/material", "/volumes/*/transform",
                                    "/volumes/*/instances"});
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame());
    const glm::vec3 extent = lightGridExtent(inputs);
    // The grid and its mask alone. Every method that reads it needs more memory than this, so a
    // method fits at this resolution or below, and its own warning names its own memory.
    const GridCost cost{[](glm::ivec3 d) { return size_t(d.x) * d.y * d.z * (sizeof(float) + 1); },
                        [](glm::ivec3 d) { return uint64_t(d.x) * d.y * d.z < uint64_t(INT32_MAX); }, "light grid"};
    std::string unused_warning;
    resolution_ = fitGridResolution(extent, cappedLightResolution(extent, scene.effects.light_resolution),
                                    size_t(scene.effects.light_memory_mb) << 20, cost, "light grid", unused_warning);
    grid_ = buildLightGrid(inputs, resolution_);
    if (grid_.clamped_cells) run.warnings.push_back(clampedCellsWarning(grid_));
}

}  // namespace voxlux
