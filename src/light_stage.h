// Light-cache stage (Schlegel 2011): light grid -> extinction SAT -> ambient-occlusion and
// shadow-cone channels. It keeps what it built and, on the next frame or scene edit, rebuilds
// only what the change invalidates: the grid and SAT when the volume, material or grid settings
// change, the AO channels when those or the AO knobs change, one light's channel when that light
// or the cone knobs change.
#pragma once
#include <string>
#include <vector>

#include "kernel_backend.h"
#include "light_cache.h"
#include "light_grid.h"
#include "render_plan.h"
#include "scene.h"
#include "stage_clock.h"
#include "summed_volume.h"

namespace voxlux {

class LightStage {
public:
    // Brings the cache up to date for `scene`, whose volume content `volume_key` identifies, and
    // points `inputs` at it. Appends the passes that ran to `times` and the parts kept from
    // before to `reused`.
    void update(const Scene& scene, const std::string& volume_key, KernelInputs& inputs, KernelBackend& backend,
                StageTimes& times, std::vector<std::string>& reused, std::vector<std::string>& warnings);

    const LightGrid& grid() const { return grid_; }
    const SummedVolume& sat() const { return sat_; }
    const LightCache& cache() const { return cache_; }

private:
    // Light grid and SAT from scratch; every channel is then stale.
    void rebuildGrid(const KernelInputs& inputs, int resolution, float bleeding, KernelBackend& backend,
                     StageClock& clock, std::vector<std::string>& warnings);
    // Runs `pass` into `channel` unless the channel was computed from `key`; true if it ran.
    bool fillChannel(LightPass& pass, int channel, const std::string& key, KernelBackend& backend);

    std::string grid_key_;
    LightGrid grid_;
    SummedVolume sat_;
    uint64_t sat_generation_ = 0;
    LightCache cache_;
    std::vector<std::string> channel_keys_;   // what each channel was computed from
};

}  // namespace voxlux
