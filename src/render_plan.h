// The render as a small graph of stages (load -> brick -> classify -> light cache -> march ->
// grade -> write). Each stage names its inputs and whether the scene needs it, with the reason,
// so `voxlux render --explain` can show why a pass runs or is skipped. Lighting passes from the
// SAT and propagation methods are added here as stages, not as branches inside the march.
#pragma once
#include <string>
#include <vector>

#include "scene.h"

namespace voxlux {

struct PlannedStage {
    std::string name;
    std::vector<std::string> inputs;   // stages or scene keys it reads
    bool runs = true;
    std::string reason;
};

std::vector<PlannedStage> planRender(const Scene& scene);

// What the scene asks of the light cache.
bool needsAmbientOcclusion(const Scene& scene);   // AO on and an ambient light to occlude
bool needsConeShadows(const Scene& scene);        // sat_cone shadows and a light to shadow
bool needsPropagation(const Scene& scene);        // propagation shadows and a light to propagate
bool needsGrade(const Scene& scene);              // grade steps, another output space, or a preview
bool stageRuns(const std::vector<PlannedStage>& plan, const std::string& name);
std::string explainPlan(const std::vector<PlannedStage>& plan);

}  // namespace voxlux
