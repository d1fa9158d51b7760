// Everything the march kernel reads, gathered from the scene and the earlier stages' outputs.
// Both backends take this one struct: the CPU backend points at its arrays, the GL backend uploads
// them. The light stages build theirs without a camera, light cache or illumination volume.
#pragma once
#include <vector>

#include "volume/brick_atlas.h"
#include "optics/emission.h"
#include "lighting/propagation/kernel/illumination_volume.h"
#include "kernel/kernel_types.h"
#include "lighting/extinction_sat/kernel/light_cache.h"
#include "volume/page_table.h"
#include "scene/scene.h"

namespace voxlux {

struct KernelInputs {
    kernel::VxParams params{};
    std::vector<kernel::VxLight> lights;
    std::vector<glm::vec4> tf_lut;          // VX_TF_LUT_SIZE entries; a constant row if unused
    std::vector<glm::vec4> emission_lut;    // VX_EMISSION_LUT_SIZE rows per emission source
    const BrickAtlas* atlas = nullptr;
    const PageTable* pages = nullptr;
    const LightCache* light_cache = nullptr;             // the light_cache stage's output, or none
    const IlluminationVolume* illumination = nullptr;    // the propagation or eye_pass stage's, or none
    std::vector<glm::vec4> noise;           // perturbation table, empty without perturbation
    glm::ivec4 region{0};                   // the pixels [x0, y0) to [x1, y1) to march (render.region)
};

// The stage outputs the march reads besides the medium (each optional).
struct MarchSources {
    const Camera* camera = nullptr;                      // resolved: the scene's, or the framing
    const LightCache* light_cache = nullptr;
    const IlluminationVolume* illumination = nullptr;
};

// `frame` (the sequence frame) animates the perturbation. `xyz_to_working` takes blackbody
// emission from CIE XYZ (D65) to the working space.
KernelInputs makeKernelInputs(const Scene& scene, const BrickAtlas& atlas, const PageTable& pages,
                              float frame = 0.0f, const glm::mat3& xyz_to_working = kXyzD65ToAcescg,
                              const MarchSources& sources = {});

}  // namespace voxlux
