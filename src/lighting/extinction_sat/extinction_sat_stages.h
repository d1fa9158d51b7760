// Extinction-SAT lighting (Schlegel 2011) as three stages of the render graph:
//  light_grid   the visible bricks' extinction, box-filtered into a dense grid over the occupied
//               bricks' box (Sec. 3, Fig. 11), with three colour-bleeding planes when asked;
//  sat          its 3D summed-area table, in integers, so every box sum is exact;
//  light_cache  per grid cell, the optical depth of the ambient-occlusion shells and of each
//               light's cone of cuboids, each read from the SAT in O(1) per cuboid.
// Cost: light_grid and sat are linear in grid cells; light_cache is cells x (shells + lights x
// cuboids) SAT queries, recomputed only for the channels a change invalidates: a moved light
// recomputes its own channel, a brighter one none.
#pragma once
#include <string>
#include <vector>

#include "lighting/extinction_sat/kernel/light_cache.h"
#include "lighting/light_grid.h"
#include "graph/render_graph.h"
#include "lighting/extinction_sat/sat_passes.h"
#include "lighting/extinction_sat/summed_volume.h"
#include "volume/volume_stages.h"

namespace voxlux {

class LightGridStage final : public Stage {
public:
    LightGridStage(const BrickStage& brick, const ClassifyStage& classify) : brick_(brick), classify_(classify) {}
    std::string name() const override { return "light_grid"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return classify_.pages().empty(); }
    void release() override { grid_ = LightGrid{}; }
    const LightGrid& grid() const { return grid_; }
    int resolution() const { return resolution_; }   // cells along the longest side, as fitted

private:
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    LightGrid grid_;
    int resolution_ = 0;
};

class SatStage final : public Stage {
public:
    explicit SatStage(const LightGridStage& grid) : grid_(grid) {}
    std::string name() const override { return "sat"; }
    StageReads reads() const override { return {{"/render/backend"}, {"light_grid"}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return grid_.grid().cells() == 0; }
    void release() override { sat_ = SummedVolume{}; }
    const SummedVolume& sat() const { return sat_; }
    uint64_t generation() const { return generation_; }   // changes whenever the SAT's contents do

private:
    const LightGridStage& grid_;
    OnDevice<SatPasses> passes_{makeSatPasses};
    SummedVolume sat_;
    uint64_t generation_ = 0;
};

class LightCacheStage final : public Stage {
public:
    LightCacheStage(const BrickStage& brick, const ClassifyStage& classify, const LightGridStage& grid, const SatStage& sat)
        : brick_(brick), classify_(classify), grid_(grid), sat_(sat) {}
    std::string name() const override { return "light_cache"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return grid_.grid().cells() == 0; }
    void release() override;
    const LightCache& cache() const { return cache_; }

private:
    // Runs `pass` into `channel` unless the channel was computed from `key`; true if it ran.
    bool fillChannel(LightPass& pass, int channel, const std::string& key, SatPasses& passes);

    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const LightGridStage& grid_;
    const SatStage& sat_;
    OnDevice<SatPasses> passes_{makeSatPasses};
    LightCache cache_;
    std::vector<std::string> channel_keys_;   // what each channel was computed from
};

}  // namespace voxlux
