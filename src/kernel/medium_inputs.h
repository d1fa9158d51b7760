// The kernel inputs a stage makes over the medium the volume stages hold: one volume's bricks and
// page table (brick, classify), or of several volumes (rendersAsSeveral: instances counted, or a
// volume that is not visible) the joined bricks of the volumes stage, each volume placed. The
// march and every light stage reach the medium here.
#pragma once
#include "kernel/kernel_inputs.h"
#include "volume/volume_stages.h"

namespace voxlux {

KernelInputs mediumInputs(const Scene& scene, const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes,
                          float frame, const glm::mat3& xyz_to_working = kXyzD65ToAcescg, MarchSources sources = {});

}  // namespace voxlux
