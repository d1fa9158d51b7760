// The light grid as one stage of the render graph, shared by the lighting methods that read it:
// the visible bricks' extinction box-filtered into a dense grid over the occupied bricks' box
// (Schlegel 2011, Sec. 3 and Fig. 11). The extinction-SAT's summed-area table and the
// propagation's illumination volume (Ropinski 2010) both sweep or sum this one grid, so a scene
// with both builds it once. What only one method needs (the colour-bleeding planes, the emitted
// radiance) that method adds in its own stage, so editing it never re-runs the other.
// Cost: one pass over the occupied voxels, linear in them; a float and a byte (the `needed` mask) per
// cell.
#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "graph/render_graph.h"
#include "lighting/light_grid.h"
#include "volume/volume_stages.h"

namespace voxlux {

// Why every light stage is skipped under render.method = reference.
inline const char* const kReferenceComputesAllLight = "skipped: the Monte Carlo reference (render.method) computes all light itself";

// A lighting method that reads the shared grid: its name, and whether it runs for a scene.
struct LightGridReader {
    std::string name;
    std::function<bool(const Scene&)> runs;
};

class LightGridStage final : public Stage {
public:
    LightGridStage(const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes)
        : brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)) {}
    // A lighting method that sums or sweeps the grid says so as its stages are made: the grid is
    // built when one of its readers runs.
    void addReader(LightGridReader reader) { readers_.push_back(std::move(reader)); }
    std::string name() const override { return "light_grid"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return noVisibleBricks(classify_, volumes_); }
    void release() override { grid_ = LightGrid{}; }
    const LightGrid& grid() const { return grid_; }
    // Cells along the longest side: effects.light_resolution, lowered only where the grid alone
    // would not fit effects.light_memory_mb. A method whose own memory lowers it further builds a
    // grid of its own at its resolution (and warns).
    int resolution() const { return resolution_; }

private:
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    std::vector<LightGridReader> readers_;
    LightGrid grid_;
    int resolution_ = 0;
};

}  // namespace voxlux
