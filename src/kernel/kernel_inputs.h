// Everything the march kernel reads, gathered from the scene and the earlier stages' outputs.
// Both backends take this one struct: the CPU backend points at its arrays, the GL backend uploads
// them. The light stages build theirs without a camera or the lighting methods' outputs.
#pragma once
#include <string>
#include <vector>

#include "volume/brick_atlas.h"
#include "optics/emission.h"
#include "kernel/kernel_types.h"
#include "volume/page_table.h"
#include "volume/scene_bricks.h"
#include "scene/scene.h"

namespace voxlux {

// One of the kernel's arrays by its storage block's name (the kernel contract's, e.g.
// "LightCache"): its first byte and length, owned by the stage that made it.
struct KernelArrayRef {
    std::string block;
    const void* data = nullptr;
    size_t bytes = 0;
};

// What the lighting methods hand the march: each method's parameter block (its member of
// VxLighting; zero, its "off", when it does not run) and the arrays its hooks read.
struct MarchLighting {
    kernel::VxLighting blocks{};
    std::vector<KernelArrayRef> arrays;
    glm::vec3 ambient_scale{1.0f};   // the share of the ambient light the methods keep (multiple scattering)

    // Sets the array of `block`, replacing an earlier method stage's.
    void setArray(const std::string& block, const void* data, size_t bytes);
};

struct KernelInputs {
    kernel::VxParams params{};
    std::vector<kernel::VxLight> lights;
    std::vector<glm::vec3> group_ambient;   // the ambient radiance per light group (VxLight::group),
                                            // which params.ambient sums
    struct Environment {                    // an environment light's map, which only the reference
        std::shared_ptr<const EnvironmentMap> map;   // and the background read (the march takes its
        int group = 0;                               // median-cut lights)
        bool visible_to_camera = false;
    };
    std::vector<Environment> environments;
    std::vector<glm::vec4> tf_lut;          // VX_TF_LUT_SIZE entries, a constant row if unused; of several
                                            // volumes, each one's table after (VxVolume::transfer_row)
    std::vector<glm::vec4> emission_lut;    // VX_EMISSION_LUT_SIZE rows per emission source
    const BrickAtlas* atlas = nullptr;
    const PageTable* pages = nullptr;
    glm::mat4 index_to_world{1.0f};         // the atlas's, placed by the volume's transform at the frame
                                            // (of several volumes: the first's)
    std::vector<kernel::VxVolume> volumes;  // of several (params.volume_count): each one's pages,
                                            // placement and material; empty for one
    MarchLighting lighting;                 // the lighting methods' blocks and arrays
    std::vector<glm::vec4> noise;           // perturbation table, empty without perturbation
    const std::vector<float>* holdout = nullptr;   // per pixel, the depth holdouts' camera-space Z
                                                   // (HoldoutStage::depth); null without holdouts
    glm::ivec4 region{0};                   // the pixels [x0, y0) to [x1, y1) to march (render.region)
};

// The stage outputs the march reads besides the medium (each optional).
struct MarchSources {
    const Camera* camera = nullptr;                      // resolved: the scene's, or the framing
    MarchLighting lighting;
    const SceneBricks* volumes = nullptr;                // of several volumes: their joined bricks,
                                                         // whose atlas and pages are the ones given
    const std::vector<float>* holdout = nullptr;         // the depth holdouts' (HoldoutStage::depth)
};

// `frame` (the sequence frame) animates the perturbation and poses the volume's transform (the
// stage reads withPlacementKeys, volume_stages.h). `xyz_to_working` takes blackbody emission from CIE XYZ (D65) to the
// working space.
KernelInputs makeKernelInputs(const Scene& scene, const BrickAtlas& atlas, const PageTable& pages,
                              float frame = 0.0f, const glm::mat3& xyz_to_working = kXyzD65ToAcescg,
                              const MarchSources& sources = {});

}  // namespace voxlux
