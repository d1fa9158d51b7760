// Illumination propagation as one unit: the sweeps' grid (illumination_grid), the lights swept
// into the illumination volume (propagation) and the indirect light swept towards the camera
// (eye_pass), whose volume the march reads, the eye pass's over the propagation's. Reports each
// frame's light update (selective or entire, and why). The stages and their costs:
// propagation_stages.h.
#include "lighting/propagation/propagation_method.h"

#include <algorithm>

#include "lighting/propagation/propagation_stages.h"

namespace voxlux {
namespace {

class PropagationMethod final : public LightingMethod {
public:
    explicit PropagationMethod(const SharedStages& shared)
        : grid_(shared.color_space, shared.xyz_to_working, shared.brick, shared.classify, shared.volumes, shared.light_grid),
          propagation_(shared.brick, shared.classify, shared.volumes, grid_),
          eye_pass_(shared.brick, shared.classify, shared.volumes, shared.camera, grid_, propagation_) {
        shared.light_grid.addReader({"the illumination volume", illuminationVolumeRuns});
    }
    std::vector<Stage*> stages() override { return {&grid_, &propagation_, &eye_pass_}; }
    std::vector<const MarchLightingStage*> marchInputs() const override { return {&propagation_, &eye_pass_}; }

    std::optional<LightUpdate> lightUpdate(const std::vector<StageReport>& frame) const override {
        const auto report = std::find_if(frame.begin(), frame.end(), [&](const StageReport& r) { return r.name == propagation_.name(); });
        if (report == frame.end() || report->status == StageStatus::Skipped) return std::nullopt;
        if (report->status == StageStatus::Ran) return propagation_.lastUpdate();
        LightUpdate kept;   // reused: nothing the sweeps read changed
        kept.mode = LightUpdate::Mode::Kept;
        kept.lights = propagation_.lastUpdate().lights;
        return kept;
    }

private:
    IlluminationGridStage grid_;
    PropagationStage propagation_;
    EyePassStage eye_pass_;
};

}  // namespace

std::unique_ptr<LightingMethod> makePropagationMethod(const SharedStages& shared) {
    return std::make_unique<PropagationMethod>(shared);
}

}  // namespace voxlux
