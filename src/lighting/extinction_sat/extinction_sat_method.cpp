// Extinction-SAT lighting as one unit: the summed-area table of the shared light grid (sat) and
// the light cache of AO shells and shadow cones read from it (light_cache), which the march reads.
// The stages and their costs: extinction_sat_stages.h.
#include "lighting/extinction_sat/extinction_sat_method.h"

#include "lighting/extinction_sat/extinction_sat_stages.h"

namespace voxlux {
namespace {

class ExtinctionSatMethod final : public LightingMethod {
public:
    explicit ExtinctionSatMethod(const SharedStages& shared)
        : sat_(shared.brick, shared.classify, shared.volumes, shared.light_grid),
          light_cache_(shared.brick, shared.classify, shared.volumes, sat_) {
        shared.light_grid.addReader({"the SAT", lightCacheRuns});
    }
    std::vector<Stage*> stages() override { return {&sat_, &light_cache_}; }
    std::vector<const MarchLightingStage*> marchInputs() const override { return {&light_cache_}; }

private:
    SatStage sat_;
    LightCacheStage light_cache_;
};

}  // namespace

std::unique_ptr<LightingMethod> makeExtinctionSatMethod(const SharedStages& shared) {
    return std::make_unique<ExtinctionSatMethod>(shared);
}

}  // namespace voxlux
