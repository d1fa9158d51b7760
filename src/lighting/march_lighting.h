// The stages whose outputs the march reads: a lighting method's last stages (the light cache, the
// illumination volume). The march holds them as a list and asks each, in order, to point the
// march's sources at its output, so the march names no method and its graph edges come from the
// list (MarchStage::reads).
// Cost: none; an interface.
#pragma once
#include "graph/render_graph.h"

namespace voxlux {

struct MarchSources;

class MarchLightingStage : public Stage {
public:
    // Points `sources` at this stage's output when it holds one; a later stage of the march's list
    // overrides what an earlier one set (the eye pass's volume over the propagation's).
    virtual void lightTheMarch(MarchSources& sources) const = 0;
};

}  // namespace voxlux
