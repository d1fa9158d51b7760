// Depth holdouts (scene key `holdouts`, docs/compositing.md) as a stage of the render graph: each
// holdout's depth image for the frame, read pixel for pixel at the render's resolution (or in
// whole blocks of pixels at a fraction of it: the viewer's coarse levels), turned into camera-space
// Z where it holds ray distances, and the nearest surface of them all kept per pixel: where the
// march and the reference stop each camera ray (vx_holdout_distance).
// Cost: reading the images; 4 bytes a pixel.
#pragma once
#include <vector>

#include "graph/render_graph.h"

namespace voxlux {

class CameraStage;

class HoldoutStage final : public Stage {
public:
    explicit HoldoutStage(const CameraStage& camera) : camera_(input(camera)) {}
    std::string name() const override { return "holdouts"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void release() override { depth_ = std::vector<float>(); }
    // Per pixel, row 0 at the top: the camera-space Z of the nearest holdout surface, or the
    // largest float where there is none. Empty without holdouts.
    const std::vector<float>& depth() const { return depth_; }

private:
    const CameraStage& camera_;
    std::vector<float> depth_;
};

}  // namespace voxlux
