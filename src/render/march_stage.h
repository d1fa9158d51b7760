// The march (or, with render.method "reference", the Monte Carlo reference) as a stage of the
// render graph: every camera ray through the bricks, reading the lighting the earlier stages left
// as typed outputs (the light cache, the illumination volume) and the scene's own light.
// Cost: pixels x samples per ray; empty bricks are skipped by the page table's DDA.
#pragma once
#include <vector>

#include "graph/render_graph.h"
#include "kernel/kernel_backend.h"
#include "reference/reference_renderer.h"

namespace voxlux {

class BrickStage;
class CameraStage;
class HoldoutStage;
class ClassifyStage;
class VolumesStage;
class EmptyFrameStage;
class ColorSpaceStage;
class MarchLightingStage;

class MarchStage final : public Stage {
public:
    // `lighting`: the lighting methods' stages the march reads (MarchLightingStage), in the order
    // they set its sources.
    MarchStage(const ColorSpaceStage& color, const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes,
               const EmptyFrameStage& empty_check, const CameraStage& camera, const HoldoutStage& holdouts,
               std::vector<const MarchLightingStage*> lighting);
    std::string name() const override { return "march"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void release() override;
    const RenderImage& image() const { return image_; }
    // The lighting methods' stages the march reads, in the order they hand it their outputs.
    const std::vector<const MarchLightingStage*>& lightingStages() const { return lighting_; }
    // For an interactive render: keep the reference's per-pixel sums (ReferenceSums, 144 bytes a
    // pixel), so that when only render.reference.spp grows the new samples are added to the
    // image instead of starting it again.
    void keepReferenceSums(bool keep) { keep_sums_ = keep; }

private:
    const ColorSpaceStage& color_;
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    const CameraStage& camera_;
    const HoldoutStage& holdouts_;
    std::vector<const MarchLightingStage*> lighting_;
    RenderImage image_;
    bool keep_sums_ = false;
    std::string referenceSetupKey(const StageRun& run) const;
    ReferenceSums sums_;
    std::string sums_key_;   // everything the march read for sums_ but the sample count
};

}  // namespace voxlux
