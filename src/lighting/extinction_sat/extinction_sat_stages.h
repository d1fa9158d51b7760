// Extinction-SAT lighting (Schlegel 2011) as two stages of the render graph, over the shared
// light grid (src/lighting/light_grid_stage.h: the visible bricks' extinction box-filtered into a
// dense grid, Sec. 3, Fig. 11):
//  sat          its 3D summed-area table, in integers, so every box sum is exact; with three
//               colour-bleeding planes when ambient occlusion bleeds colour;
//  light_cache  per grid cell, the optical depth of the ambient-occlusion shells and of each
//               light's cone of cuboids, each read from the SAT in O(1) per cuboid.
// Cost: sat is linear in grid cells (and in the occupied voxels when it walks them for a grid of
// its own: colour bleeding with a varying albedo, or a budget below the shared grid's); light_cache is cells x (shells + lights x cuboids) SAT
// queries, recomputed only for the channels a change invalidates: a moved light recomputes its own
// channel, a brighter one none. Light linking: a link set whose lights only some volumes shadow
// (lights[i].shadow_volumes) has a SAT of those volumes' extinction of its own, which its lights'
// cones read: a grid and a SAT more per such set.
#pragma once
#include <string>
#include <vector>

#include "lighting/extinction_sat/kernel/light_cache.h"
#include "lighting/light_grid_stage.h"
#include "lighting/march_lighting.h"
#include "graph/render_graph.h"
#include "lighting/extinction_sat/sat_passes.h"
#include "lighting/extinction_sat/summed_volume.h"
#include "volume/volume_stages.h"

namespace voxlux {

// Whether a scene needs the light cache (ambient occlusion or SAT-cone shadows), and so the SAT.
bool lightCacheRuns(const Scene& scene);

class SatStage final : public Stage {
public:
    SatStage(const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes, const LightGridStage& shared)
        : brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)), shared_(input(shared)) {}
    std::string name() const override { return "sat"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return shared_.grid().cells() == 0; }
    void release() override;
    // The grid the SAT sums: the shared light grid, or a copy with the colour-bleeding planes, or
    // a coarser grid of its own where the SAT and cache would not fit effects.light_memory_mb.
    const LightGrid& grid() const { return own_grid_.cells() > 0 ? own_grid_ : shared_.grid(); }
    int resolution() const { return resolution_; }   // cells along the longest side, as fitted
    const SummedVolume& sat() const { return sat_; }
    uint64_t generation() const { return generation_; }   // changes whenever the SAT's contents do
    // The SAT link set `link`'s lights' cones read (light linking), and its generation: its own
    // where only some volumes shadow them, else sat().
    const SummedVolume& satOf(int link) const;
    uint64_t generationOf(int link) const;

private:
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    const LightGridStage& shared_;
    OnDevice<SatPasses> passes_{makeSatPasses};
    LightGrid own_grid_;   // no cells when the shared grid is summed as it is
    int resolution_ = 0;
    SummedVolume sat_;
    uint64_t generation_ = 0;
    std::vector<SummedVolume> linked_sats_;   // per link set: empty where every volume shadows its lights
    std::vector<uint64_t> linked_generations_;
};

class LightCacheStage final : public MarchLightingStageOf<LightCache> {
public:
    LightCacheStage(const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes, const SatStage& sat)
        : brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)), sat_(input(sat)) {}
    std::string name() const override { return "light_cache"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return sat_.grid().cells() == 0; }
    void release() override;
    const LightCache& cache() const { return cache_; }
    void lightTheMarch(const Scene& scene, MarchLighting& lighting) const override;
    const LightCache* marchOutput() const override { return cache_.channels > 0 ? &cache_ : nullptr; }

private:
    // Runs `pass` into `channel` unless the channel was computed from `key`; true if it ran.
    bool fillChannel(LightPass& pass, int channel, const std::string& key, SatPasses& passes);

    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    const SatStage& sat_;
    OnDevice<SatPasses> passes_{makeSatPasses};
    LightCache cache_;
    std::vector<std::string> channel_keys_;   // what each channel was computed from
};

}  // namespace voxlux
