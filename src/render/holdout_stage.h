// Holdouts (scene key `holdouts`, docs/compositing.md) as a stage of the render graph: where each
// camera ray stops. A depth holdout's image for the frame is read pixel for pixel at the render's
// resolution (or in whole blocks of pixels at a fraction of it: the viewer's coarse levels) and
// turned into camera-space Z where it holds ray distances; a mesh holdout's triangles (placed at
// the frame) are met by each pixel's central camera ray through Embree (render/mesh_rays.h). The
// nearest surface of them all is kept per pixel: where the march and the reference stop each
// camera ray (vx_holdout_distance).
// Cost: reading the images; one BVH over the meshes and one ray a pixel; 4 bytes a pixel.
#pragma once
#include <vector>

#include "graph/render_graph.h"

namespace voxlux {

class CameraStage;
class HoldoutMeshStage;

class HoldoutStage final : public Stage {
public:
    HoldoutStage(const CameraStage& camera, const HoldoutMeshStage& meshes) : camera_(input(camera)), meshes_(input(meshes)) {}
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
    const HoldoutMeshStage& meshes_;
    std::vector<float> depth_;
};

}  // namespace voxlux
