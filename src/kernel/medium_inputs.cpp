#include "kernel/medium_inputs.h"

namespace voxlux {

KernelInputs mediumInputs(const Scene& scene, const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes,
                          float frame, const glm::mat3& xyz_to_working, MarchSources sources) {
    if (!rendersAsSeveral(scene)) return makeKernelInputs(scene, brick.atlas(), classify.pages(), frame, xyz_to_working, sources);
    sources.volumes = &volumes.bricks();
    return makeKernelInputs(scene, volumes.bricks().atlas, volumes.bricks().pages, frame, xyz_to_working, sources);
}

}  // namespace voxlux
