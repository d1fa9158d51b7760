#include "grade/color_stages.h"

#include <algorithm>

#include "core/error.h"

namespace voxlux {

bool needsGrade(const Scene& s) {
    const ColorSettings& c = s.color;
    return !c.grade.empty() || (!c.output_space.empty() && c.output_space != c.working_space) || !s.output.preview.empty() ||
           s.render.exposure != 0.0f;
}

StageActivity ColorSpaceStage::activity(const Scene& s) const {
    return {true, "OCIO config " + (s.color.config.empty() ? std::string("from $OCIO or built in") : "'" + s.color.config + "'") +
                      ", working space " + (s.color.working_space.empty() ? "the scene_linear role" : "'" + s.color.working_space + "'")};
}

void ColorSpaceStage::run(StageRun& run) {
    working_.reset();
    const Scene& scene = run.scene({"/color/config", "/color/working_space", "/volumes/*/emission/*/kind"});
    ColorPipeline p = resolveWorkingSpace(scene.color);
    const bool blackbody = std::any_of(scene.volumes.begin(), scene.volumes.end(), [](const VolumeSpec& v) {
        return v.enabled && std::any_of(v.emission.begin(), v.emission.end(), [](const EmissionSource& e) { return e.kind == EmissionKind::Blackbody; });
    });
    if (blackbody && !p.xyz_to_working)
        throw InputError(p.config_source + ": has no linear cie_xyz_d65_interchange role into '" + p.working_space +
                         "', which blackbody emission needs");
    working_ = std::move(p);
}

StageActivity ColorTransformsStage::activity(const Scene& s) const {
    const ColorSettings& c = s.color;
    std::string out = std::to_string(c.grade.size()) + (c.grade.size() == 1 ? " grade step" : " grade steps") + ", output " +
                      (c.output_space.empty() ? std::string("in the working space") : "'" + c.output_space + "'");
    if (!s.output.preview.empty())
        out += ", preview through " + (c.display.empty() ? std::string("the default display") : "'" + c.display + "'") +
               (c.view.empty() ? "" : " / '" + c.view + "'");
    return {true, out};
}

void ColorTransformsStage::run(StageRun& run) {
    pipeline_.reset();
    const Scene& scene = run.scene({"/color", "/output/preview"});
    pipeline_ = buildColorTransforms(space_.working(), scene.color, !scene.output.preview.empty());
}

}  // namespace voxlux
