// Illumination propagation (Ropinski 2010 with the Kniss 2003 optical model; Sunden 2015 for many
// lights) as three stages of the render graph:
//  illumination_grid  the shared light grid (src/lighting/light_grid_stage.h) as the sweeps' grid,
//                     with the emitted radiance when it lights the medium, its 2^3 average for
//                     chroma-subsampled indirect light, and a 2D transfer function's per-material
//                     transport (extinction times -ln(transport colour), three planes) for it;
//  propagation        every light swept slice by slice through the grid, grouped into at most six
//                     passes, adding its direct and (blurred, transport-attenuated) indirect RGB
//                     into one illumination volume. When only lights change it takes the changed
//                     lights out and puts their new state in (a selective update), unless an
//                     entire update is estimated to cost less or past updates' float residue needs
//                     a re-base;
//  eye_pass           the indirect light swept once more towards the camera (Ropinski Sec. 4.1):
//                     the propagation's volume with its indirect block replaced, so a camera move
//                     re-runs this sweep alone.
// Light groups and light linking: the volume holds a block per light group and link set
// (vx_light_block), each light's sweeps adding into its own; a link set whose lights only some
// volumes shadow (lights[i].shadow_volumes) sweeps over a grid of those volumes' extinction, one
// more grid (and its coarsening) per such set.
// Cost: each sweep is linear in the cells it walks; a point light's sweep costs about 2 directional
// ones and an indirect one 4 (SweepCost), which is what the selective update weighs.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "lighting/propagation/kernel/illumination_volume.h"
#include "lighting/light_update.h"
#include "lighting/light_grid_stage.h"
#include "lighting/march_lighting.h"
#include "lighting/propagation/propagation_passes.h"
#include "graph/render_graph.h"
#include "volume/volume_stages.h"

namespace voxlux {

// Bytes the propagation stages need at light-grid dimensions `dims`: the light grid, the direct
// RGB, an x pass's slice-major copies, and with indirect light the indirect cells (their own
// extinction grid when chroma subsampled, and the eye pass's second volume and input copy of the
// indirect cells), and with `emission` the emission grids and their sweeps' blocks (with
// `scattering`, of several volumes, their scattering grids too), and a volume for each of `blocks`
// (light groups, lightGroupMarches, times link sets). The lights' 2D slice buffers are left out: two slices per light.
size_t illuminationBytes(glm::ivec3 dims, bool indirect, int chroma, bool emission, bool transport, bool scattering = false,
                         int blocks = 1);

// Whether `scene` lights the march from an illumination volume: propagation shadows, a light or
// lit emission to propagate, and not the Monte Carlo reference.
bool illuminationVolumeRuns(const Scene& scene);

// The weights of the estimate that picks a selective or an entire update, in units of one
// directional direct sweep over the same cells: CPU figures measured by voxlux_bench_multilight
// (docs/performance-multilight.md). They only have to order the two choices.
struct SweepCost {
    static constexpr double kPass = 0.7;        // a pass's own walk over the extinction and the volume
    static constexpr double kPointSweep = 2.0;  // a point or spot light's sweep (its own step per cell)
    static constexpr double kIndirect = 4.0;    // times this for an indirect sweep (RGB, blurred)
    static constexpr double kXAxis = 1.2;       // times this for an x pass (slice-major copies)
};

// The volume is re-based (an entire update) before the light swept in and out since the last
// entire update exceeds this many times the light present, as peak radiance: adding and later
// subtracting a light of peak m leaves a float residue of about m * 2^-24 per cell, so the residue
// stays under ~4e-6 of the light present (tests measure it).
constexpr double kDriftBudget = 64.0;

// A grid the sweeps run over: the light grid, or its chroma-subsampled coarsening.
struct SweepGrid {
    glm::mat4 grid_to_world{1.0f};
    glm::mat4 world_to_grid{1.0f};
    glm::ivec3 dims{0};
    float cells_per_voxel = 1.0f;          // grid cells per index voxel (for displacement)
    const std::vector<float>* sigma = nullptr;   // the extinction; with transport_planes, 3 planes after it
    uint64_t sigma_generation = 0;         // changes whenever sigma does (PropagationPass)
    bool transport_planes = false;         // sigma is 4 planes: the extinction, then it times
                                           // -ln(transport colour) per channel (VxPropParams)
    const std::vector<float>* emission = nullptr;   // RGB emitted radiance per cell, when it lights the medium
    const std::vector<float>* scattering = nullptr; // with it, of several volumes: RGB scattering coefficient per cell
};

class IlluminationGridStage final : public Stage {
public:
    // `xyz_to_working`: the matrix of `color_space` (a stage of a higher layer, grade), which
    // emission colours are converted by.
    IlluminationGridStage(const Stage& color_space, std::function<glm::mat3()> xyz_to_working, const BrickStage& brick,
                          const ClassifyStage& classify, const VolumesStage& volumes, const LightGridStage& shared)
        : xyz_to_working_(std::move(xyz_to_working)), brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)),
          shared_(input(shared)) {
        input(color_space);
    }
    std::string name() const override { return "illumination_grid"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return noVisibleBricks(classify_, volumes_); }
    void release() override;
    // The grid direct light sweeps over, and the one indirect light sweeps over (the same grid
    // unless chroma subsampled).
    const SweepGrid& fine() const { return fine_; }
    const SweepGrid& coarse() const { return coarse_; }
    // The grids link set `link`'s lights sweep over: their own where only some volumes shadow them
    // (light linking), else fine() and coarse().
    bool ownShadows(int link) const { return size_t(link) < linked_.size() && linked_[size_t(link)].fine.sigma; }
    const SweepGrid& fineOf(int link) const { return ownShadows(link) ? linked_[size_t(link)].fine : fine_; }
    const SweepGrid& coarseOf(int link) const { return ownShadows(link) ? linked_[size_t(link)].coarse : coarse_; }
    uint64_t generation() const { return generation_; }   // changes whenever the grids do

private:
    std::function<glm::mat3()> xyz_to_working_;
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    const LightGridStage& shared_;
    LightGrid own_grid_;   // empty unless this volume's memory lowered its resolution below the shared grid's
    std::vector<float> emission_;   // RGB emitted radiance per cell, when it lights the medium
    std::vector<float> scattering_; // with it, of several volumes: RGB scattering coefficient per cell
    std::vector<float> chroma_sigma_;   // the light grid averaged over 2^3 cells (chroma subsampling)
    std::vector<float> chroma_emission_, chroma_scattering_;   // and its emission and scattering
    std::vector<float> transport_sigma_;   // the coarse grid's extinction and transport depth, with
                                           // a per-voxel transport colour (SweepGrid::transport_planes)
    SweepGrid fine_, coarse_;
    // Per link set (light linking): the extinction of the volumes that shadow its lights, where
    // only some do (no sigma otherwise).
    struct LinkedGrids {
        std::vector<float> fine_sigma, coarse_sigma;
        SweepGrid fine, coarse;
    };
    std::vector<LinkedGrids> linked_;
    uint64_t generation_ = 0;
};

class PropagationStage final : public MarchLightingStageOf<IlluminationVolume> {
public:
    PropagationStage(const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes, const IlluminationGridStage& grid)
        : brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)), grid_(input(grid)) {}
    std::string name() const override { return "propagation"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return noVisibleBricks(classify_, volumes_); }
    void release() override;
    const IlluminationVolume& volume() const { return volume_; }
    const LightUpdate& lastUpdate() const { return last_update_; }
    void lightTheMarch(const Scene& scene, MarchLighting& lighting) const override;
    const IlluminationVolume* marchOutput() const override { return volume_.values.empty() ? nullptr : &volume_; }

private:
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    const IlluminationGridStage& grid_;
    OnDevice<PropagationPasses> passes_{makePropagationPasses};
    std::string setup_key_;             // the grid and knobs the light sweeps were computed with
    std::vector<kernel::VxLight> applied_;   // the lights the volume holds
    double drift_ = 0.0;                // peak radiance swept in and out since the last entire update
    LightUpdate last_update_;
    IlluminationVolume volume_;
};

class EyePassStage final : public MarchLightingStageOf<IlluminationVolume> {
public:
    EyePassStage(const BrickStage& brick, const ClassifyStage& classify, const VolumesStage& volumes, const CameraStage& camera,
                 const IlluminationGridStage& grid, const PropagationStage& propagation)
        : brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)), camera_(input(camera)), grid_(input(grid)),
          propagation_(input(propagation)) {}
    std::string name() const override { return "eye_pass"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    bool idle() const override { return noVisibleBricks(classify_, volumes_); }
    void release() override {
        volume_ = IlluminationVolume{};
        passes_.release();
    }
    const IlluminationVolume& volume() const { return volume_; }
    void lightTheMarch(const Scene& scene, MarchLighting& lighting) const override;
    const IlluminationVolume* marchOutput() const override { return volume_.values.empty() ? nullptr : &volume_; }

private:
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
    const CameraStage& camera_;
    const IlluminationGridStage& grid_;
    const PropagationStage& propagation_;
    OnDevice<PropagationPasses> passes_{makePropagationPasses};
    IlluminationVolume volume_;
};

}  // namespace voxlux
