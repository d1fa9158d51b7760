// Everything the march kernel reads, gathered from the scene and the earlier stages. Both
// backends take this one struct: the CPU backend points at its arrays, the GL backend uploads them.
#pragma once
#include <vector>

#include "brick_atlas.h"
#include "emission.h"
#include "kernel_types.h"
#include "page_table.h"
#include "scene.h"

namespace voxlux {

struct KernelInputs {
    kernel::VxParams params{};
    std::vector<kernel::VxLight> lights;
    std::vector<glm::vec4> tf_lut;          // VX_TF_LUT_SIZE entries; a constant row if unused
    std::vector<glm::vec4> emission_lut;    // VX_EMISSION_LUT_SIZE rows per emission source
    const BrickAtlas* atlas = nullptr;
    const PageTable* pages = nullptr;
    const float* cache = nullptr;           // light cache (P.cache_dims), or none
    size_t cache_floats = 0;
    const float* illum = nullptr;           // illumination volume (P.illum_dims), or none
    size_t illum_floats = 0;
    std::vector<glm::vec4> noise;           // perturbation table, empty without perturbation
};

// `camera` must be resolved (the scene's, or the default framing). `frame` (the sequence frame)
// animates the perturbation. `xyz_to_working` takes blackbody emission from CIE XYZ (D65) to the
// working space.
KernelInputs makeKernelInputs(const Scene& scene, const Camera& camera, const BrickAtlas& atlas,
                              const PageTable& pages, float frame = 0.0f,
                              const glm::mat3& xyz_to_working = kXyzD65ToAcescg);

// Smallest world length of one voxel edge: the march step unit.
float voxelEdge(const glm::mat4& index_to_world);

}  // namespace voxlux
