// Illumination stage (Ropinski 2010 with the Kniss 2003 optical model, Sunden 2015 for many
// lights): light grid -> sweeps that carry each light's direct and indirect light through the
// illumination volume, grouped into at most six passes -> optionally the eye sweep. It keeps the
// light grid while the volume, material and resolution stay. When only lights change it takes the
// changed lights out and puts their new state in (a selective update), unless recomputing every
// light (an entire update) is estimated to cost less or the float residue of past updates needs
// a re-base. The eye sweep is kept while the lights and camera stay.
#pragma once
#include <string>
#include <vector>

#include "illumination_volume.h"
#include "kernel_backend.h"
#include "light_grid.h"
#include "scene.h"
#include "stage_clock.h"

namespace voxlux {

// Bytes the illumination stage needs at light-grid dimensions `dims`: the light grid, the direct
// RGB, an x pass's slice-major copies, and with indirect light the indirect cells (their own
// extinction grid when chroma subsampled, an input copy for the eye sweep). The lights' 2D slice
// buffers are left out: two slices per light.
size_t illuminationBytes(glm::ivec3 dims, bool indirect, int chroma, bool eye_pass);

// What one update of the light sweeps did, for logs, the light-edit report and tests.
struct LightUpdate {
    enum class Mode { Kept, Entire, Selective };
    Mode mode = Mode::Entire;
    std::string reason;          // why this mode (empty when kept)
    int lights = 0;              // lights in the volume afterwards
    int lights_out = 0;          // light states taken out (selective: the changed lights' old states)
    int lights_in = 0;           // light states put in (selective: their new states; entire: all lights)
    int sweeps = 0;              // light sweeps run, over both blocks (a light in two passes counts twice)
    int passes = 0;              // passes over the volume
    long long slices = 0;        // slices walked, over all passes
    double selective_cost = 0;   // the estimates compared (units: cells times a directional sweep's work)
    double entire_cost = 0;
};

// The weights of the estimate that picks a selective or an entire update, in units of one
// directional direct sweep over the same cells: CPU figures measured by voxlux_bench_multilight
// (docs/performance-multilight.md). They only have to order the two choices.
struct SweepCost {
    static constexpr double kPass = 0.7;        // a pass's own walk over the extinction and the volume
    static constexpr double kPointSweep = 8.0;  // a point or spot light's sweep (the per-cell kernel)
    static constexpr double kIndirect = 6.0;    // times this for an indirect sweep (RGB, blurred)
    static constexpr double kXAxis = 1.5;       // times this for an x pass (slice-major copies)
};

// The volume is re-based (an entire update) before the light swept in and out since the last
// entire update exceeds this many times the light present, as peak radiance: adding and later
// subtracting a light of peak m leaves a float residue of about m * 2^-24 per cell, so the residue
// stays under ~4e-6 of the light present (tests measure it).
constexpr double kDriftBudget = 64.0;

class IlluminationStage {
public:
    // Brings the volume up to date for `scene` (camera `camera`, whose volume content `volume_key`
    // identifies) and points `inputs` at it. Appends the passes that ran to `times` and what was
    // kept to `reused`.
    void update(const Scene& scene, const Camera& camera, const std::string& volume_key, KernelInputs& inputs,
                KernelBackend& backend, StageTimes& times, std::vector<std::string>& reused,
                std::vector<std::string>& warnings);

    const IlluminationVolume& volume() const { return volume_; }
    const LightUpdate& lastUpdate() const { return last_update_; }

private:
    std::string grid_key_;
    LightGrid grid_;
    std::vector<float> chroma_sigma_;   // the light grid averaged over 2^3 cells (chroma subsampling)
    std::string setup_key_;             // the grid and knobs the light sweeps were computed with
    std::vector<kernel::VxLight> applied_;   // the lights the volume holds
    double drift_ = 0.0;                // peak radiance swept in and out since the last entire update
    long long lights_version_ = 0;      // counts updates of the light sweeps
    LightUpdate last_update_;
    std::string eye_key_;               // what the eye sweep was computed from ("" = not applied)
    std::vector<float> before_eye_;     // the light sweeps' indirect block, while the eye sweep replaces it
    IlluminationVolume volume_;
};

}  // namespace voxlux
