#include "render_plan.h"

#include <algorithm>
#include <sstream>

namespace voxlux {

std::vector<PlannedStage> planRender(const Scene& s) {
    std::vector<PlannedStage> plan;
    std::string grids = "density '" + s.volume.density.name + "'";
    if (s.volume.emission) grids += ", emission '" + s.volume.emission->name + "'";
    if (s.volume.color) grids += ", colour '" + s.volume.color->name + "'";
    plan.push_back({"load", {"volume"}, true, "reads " + grids + " from " + s.volume.path});
    plan.push_back({"brick", {"load"}, true, "densifies active voxels into 8^3 bricks with a +1 apron"});
    plan.push_back({"classify", {"brick", "material"}, true,
                    s.material.transfer.empty() ? "drops bricks with zero density and emission"
                                                : "drops bricks the transfer function makes transparent"});
    plan.push_back({"light_cache", {"classify", "lights", "effects"}, false,
                    "skipped: no effect in the scene needs a precomputed light cache"});

    std::string march;
    if (s.lights.empty()) {
        march = "no lights: emission and transmittance only";
    } else {
        march = std::to_string(s.lights.size()) + (s.lights.size() == 1 ? " light, " : " lights, ");
        march += s.effects.shadows == ShadowMethod::Raymarch ? "ray-marched shadow rays per sample (reference)"
                                                             : "unshadowed (effects.shadows = none)";
    }
    if (s.volume.emission) march += ", emission";
    plan.push_back({"march", {"classify", "light_cache", "camera", "lights", "render"}, true, march});
    plan.push_back({"grade", {"march"}, false, "skipped: no colour transform in the scene (output is scene-linear)"});
    plan.push_back({"write", {"march", "grade", "output"}, true,
                    "EXR, " + std::string(s.output.pixel_type == PixelType::Half ? "half" : "float") + ", " +
                        s.output.compression + (s.output.aovs.empty() ? "" : ", AOVs")});
    return plan;
}

bool stageRuns(const std::vector<PlannedStage>& plan, const std::string& name) {
    auto it = std::find_if(plan.begin(), plan.end(), [&](const PlannedStage& p) { return p.name == name; });
    return it != plan.end() && it->runs;
}

std::string explainPlan(const std::vector<PlannedStage>& plan) {
    std::ostringstream out;
    for (const auto& st : plan) {
        out << (st.runs ? "run   " : "skip  ") << st.name;
        for (size_t pad = st.name.size(); pad < 12; ++pad) out << ' ';
        out << st.reason << "  [in:";
        for (const auto& i : st.inputs) out << ' ' << i;
        out << "]\n";
    }
    return out.str();
}

}  // namespace voxlux
