// The stages whose outputs the march reads: a lighting method's last stages (the light cache, the
// illumination volume). The march holds them as a list and asks each, in order, to hand it its
// output as the kernel contract's parameter block and arrays (MarchLighting), so the march names
// no method and its graph edges come from the list (MarchStage::reads).
// Cost: none; an interface.
#pragma once
#include "graph/render_graph.h"

namespace voxlux {

struct MarchLighting;

class MarchLightingStage : public Stage {
public:
    // Sets this method's block of `lighting` (and its arrays) from this stage's output under
    // `scene`, when it holds one; a later stage of the march's list overrides what an earlier one
    // set (the eye pass's volume over the propagation's). The scene keys it reads are the march's.
    virtual void lightTheMarch(const Scene& scene, MarchLighting& lighting) const = 0;
};

// One whose output is an `Output` (LightCache, IlluminationVolume), which tests and tools read
// through Renderer::lightingOutput.
template <class Output>
class MarchLightingStageOf : public MarchLightingStage {
public:
    // What the march reads of it, or null when it holds nothing.
    virtual const Output* marchOutput() const = 0;
};

}  // namespace voxlux
