// Each volume's coverage (output.aovs "coverage"): the share of a pixel's alpha that a visible
// volume of the scene holds, the light its extinction takes from the camera ray, so the planes of
// all volumes sum to the alpha. A compositor pulls a matte per element from them, as from
// Cryptomatte. Of several volumes it is a CPU pass over the march's own samples and kernel
// functions (shaders/vx_volumes.h), extinction only; its cost is a march without lighting, plus a
// lookup per volume and sample. Of one visible volume it is the alpha.
#pragma once
#include <string>
#include <vector>

#include "kernel/kernel_backend.h"
#include "kernel/kernel_inputs.h"
#include "graph/render_graph.h"
#include "render/holdout_stage.h"
#include "volume/volume_stages.h"

namespace voxlux {

// A plane per scene volume, named by it.
struct CoveragePlanes {
    std::vector<std::string> names;
    std::vector<std::vector<float>> planes;   // row-major, as RenderImage::pixels
};

// The coverage of the volumes of `inputs` (several: params.volume_count > 0), seen from its camera.
// `scene_volume[i]` is the scene volume that placed volume i belongs to (instances add to their
// volume's plane); `names` the scene volumes' names.
CoveragePlanes volumeCoverage(const KernelInputs& inputs, const std::vector<int>& scene_volume, const std::vector<std::string>& names);

// The stage: the planes when output.aovs asks for "coverage" and the scene renders as several
// volumes (rendersAsSeveral); the write stage takes one volume's from the alpha.
class CoverageStage final : public Stage {
public:
    CoverageStage(const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes, const CameraStage& camera,
                  const HoldoutStage& holdouts)
        : brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)), camera_(input(camera)), holdouts_(input(holdouts)) {}
    std::string name() const override { return "coverage"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void release() override { planes_ = CoveragePlanes{}; }
    const CoveragePlanes& planes() const { return planes_; }

private:
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    const CameraStage& camera_;
    const HoldoutStage& holdouts_;
    CoveragePlanes planes_;
};

// Whether the scene's output asks for the coverage AOV.
bool wantsCoverage(const Scene& scene);

}  // namespace voxlux
