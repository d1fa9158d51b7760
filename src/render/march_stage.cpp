#include "render/march_stage.h"

#include <algorithm>

#include "grade/color_stages.h"
#include "kernel/medium_inputs.h"
#include "lighting/march_lighting.h"
#include "lighting/propagation/emitted_light.h"
#include "lighting/propagation/propagation_stages.h"
#include "render/environment_background.h"
#include "render/holdout_stage.h"
#include "render/light_group_passes.h"
#include "scene/camera.h"
#include "volume/volume_stages.h"

namespace voxlux {
namespace {

std::string emissionDescription(const EmissionSource& e) {
    const char* kind = e.kind == EmissionKind::Blackbody ? "blackbody" : e.kind == EmissionKind::Ramp ? "ramp" : "constant";
    return std::string(kind) + " from '" + e.grid.name + "'";
}

}  // namespace

void MarchStage::release() {
    image_ = RenderImage{};
    sums_ = ReferenceSums{};
    sums_key_.clear();
}

MarchStage::MarchStage(const ColorSpaceStage& color, const BrickStage& brick, const ClassifyStage& classify,
                       const VolumesStage& volumes, const EmptyFrameStage& empty_check, const CameraStage& camera,
                       const HoldoutStage& holdouts, std::vector<const MarchLightingStage*> lighting)
    : color_(input(color)), brick_(input(brick)), classify_(input(classify)), volumes_(input(volumes)), camera_(input(camera)),
      holdouts_(input(holdouts)), lighting_(std::move(lighting)) {
    input(empty_check);   // read for its order alone: an empty frame stops before the march
    for (const MarchLightingStage* s : lighting_) input(*s);
}

// The march's key as if the reference's sample count were not read.
std::string MarchStage::referenceSetupKey(const StageRun& run) const {
    nlohmann::json document = run.scene.uncheckedDocument();
    const nlohmann::json::json_pointer spp("/render/reference/spp");
    if (document.contains(spp)) document["render"]["reference"].erase("spp");
    return stageKey(*this, document, run.keys);
}

StageReads MarchStage::reads() const {
    // Every render key but exposure, which only the grade applies.
    return {withPlacementKeys({"/render/resolution", "/render/step", "/render/shadow_step", "/render/transmittance_cutoff", "/render/filter", "/render/backend",
             "/render/method", "/render/reference", "/render/motion_blur", "/render/region", "/volumes/*/material", "/lights/*/type", "/lights/*/enabled", "/lights/*/position", "/lights/*/direction",
             "/lights/*/color", "/lights/*/intensity", "/lights/*/cone_angle", "/lights/*/cone_softness", "/effects",
             "/volumes/*/emission", "/output/deep", "/output/deep_samples", "/input/light_groups", "/input/light_links",
             // an environment's map: the reference samples it, the camera may see it
             "/lights/*/map", "/lights/*/map_colorspace", "/lights/*/up", "/lights/*/rotation", "/lights/*/visible_to_camera",
             "/input/environment_maps"})};
}

StageActivity MarchStage::activity(const Scene& s) const {
    const bool reference = s.render.method == RenderMethod::Reference;
    std::string march;
    if (reference) {
        const ReferenceSettings& ref = s.render.reference;
        march = "Monte Carlo reference: a ratio-tracked camera pass, residual-ratio-tracked shadows, up to " + std::to_string(ref.max_bounces) +
                (ref.max_bounces == 1 ? " bounce, " : " bounces, ") + std::to_string(ref.spp) + " spp";
    } else if (s.lights.empty()) {
        march = emissionLightsTheMedium(s) ? "no lights: emission, its light scattered from the illumination volume, and transmittance"
                                           : "no lights: emission and transmittance only";
    } else {
        // The environment's median-cut lights and floor are named with it, not counted as the scene's.
        const size_t own = size_t(std::count_if(s.lights.begin(), s.lights.end(), [](const Light& l) { return !l.from_environment; }));
        march = std::to_string(own) + (own == 1 ? " light, " : " lights, ");
        march += enabledLightCount(s, false) > 0 ? shadowMethodDescription(s.effects.shadows) : "ambient only";
        if (enabledLightCount(s, true) > 0)
            march += s.effects.ambient_occlusion ? ", occluded ambient" : ", unoccluded ambient";
    }
    for (size_t i = 0; i < s.lights.size(); ++i) {
        const Light& l = s.lights[i];
        if (!l.environment || !l.enabled) continue;
        const auto part = [&](LightType type) {
            return std::count_if(s.lights.begin(), s.lights.end(), [&](const Light& p) { return p.from_environment == i && p.type == type; });
        };
        march += reference ? ", the environment map sampled by importance (MIS with the phase function)"
                           : ", the environment map as " + std::to_string(part(LightType::Directional)) + " median-cut lights" +
                                 (part(LightType::Ambient) > 0 ? " and its floor as ambient" : "");
        if (l.environment->visible_to_camera) march += ", seen behind the volumes";
    }
    if (s.render.filter == Filter::Tricubic) march += ", tricubic B-spline filter";
    if (illuminationVolumeRuns(s) && s.effects.propagation.filter == Filter::Trilinear)
        march += ", illumination volume read trilinear";
    if (s.effects.surface && !reference) march += ", surface shading where the gradient is steep";
    if (s.effects.perturbation && !reference) march += ", noise-perturbed";
    if (!s.holdouts.empty()) march += ", camera rays stopped at the holdouts";
    if (s.output.deep) march += ", deep samples (up to " + std::to_string(s.output.deep_samples) + " a pixel)";
    if (const LightGroups groups = lightGroups(s); !groups.names.empty()) {
        const size_t layers = groups.names.size() + 1;
        march += reference ? ", each path's light split into " + std::to_string(layers) + " light-group layers"
                           : ", " + std::to_string(lightGroupMarches(s)) + " marches for the light groups (one a group" +
                                 (size_t(lightGroupMarches(s)) > groups.names.size() ? ", one for the emitted light)" : ")");
    }
    if (const size_t sets = lightLinks(s).sets.size(); sets > 0)
        march += ", " + std::to_string(sets) + (sets == 1 ? " link set" : " link sets") + " (light linking)";
    const bool lens = s.camera && lensRadius(*s.camera) > 0.0f;
    const int rays = std::max(s.render.motion_blur ? s.render.motion_blur->samples : 1, lens ? s.camera->lens_samples : 1);
    const std::string per_pixel = std::to_string(rays) + (rays == 1 ? " ray" : " rays") + " a pixel";
    if (s.render.motion_blur)
        march += reference ? ", motion-blurred where the medium or camera moves (a time a path)"
                           : ", motion-blurred where the medium or camera moves (" + per_pixel + ")";
    if (lens) march += reference ? ", depth of field (a point of the lens a path)" : ", depth of field (" + per_pixel + " over the lens)";
    for (const VolumeSpec& v : s.volumes) {
        if (!v.enabled || v.emission.empty() || v.role != VolumeRole::Visible) continue;
        march += ", emission" + (rendersAsSeveral(s) ? " of " + v.name : std::string()) + ": ";
        for (size_t i = 0; i < v.emission.size(); ++i) march += (i ? ", " : "") + emissionDescription(v.emission[i]);
    }
    return {true, march};
}

void MarchStage::run(StageRun& run) {
    // The march's output takes every key it declares, most through the kernel's inputs.
    const Scene& scene = run.scene(reads().keys);
    MarchSources sources;
    for (const MarchLightingStage* s : lighting_) s->lightTheMarch(scene, sources.lighting);
    sources.camera = &camera_.camera();
    sources.holdout = &holdouts_.depth();
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame(), color_.xyzToWorking(), sources);
    const LightGroups groups = lightGroups(scene);
    for (const Light& l : scene.lights)
        if (l.environment && l.enabled && l.environment->repaired_pixels > 0)
            run.warnings.push_back(l.environment->map + ": " + std::to_string(l.environment->repaired_pixels) +
                                   " pixels NaN or infinite (taken as black) or with a negative channel (taken as 0)");
    if (scene.render.method != RenderMethod::Reference) {
        image_ = groups.names.empty() ? run.backend.march(inputs) : marchLightGroups(run.backend, inputs, groups.names, lightGroupMarches(scene));
        addEnvironmentBackground(inputs, image_);
        return;
    }
    uint64_t opaque = 0;
    if (!keep_sums_) {
        image_ = renderReference(inputs, scene.render.reference, &opaque, nullptr, groups.names);
    } else {
        const std::string setup = referenceSetupKey(run);
        if (setup != sums_key_) sums_ = ReferenceSums{};
        sums_key_ = setup;
        const int kept = sums_.samples < scene.render.reference.spp ? sums_.samples : 0;
        try {
            image_ = renderReference(inputs, scene.render.reference, &opaque, &sums_, groups.names);
        } catch (...) {   // the sums may hold part of the new samples
            sums_ = ReferenceSums{};
            sums_key_.clear();
            throw;
        }
        if (kept > 0) run.reused.push_back("march: " + std::to_string(kept) + " reference samples a pixel");
    }
    addEnvironmentBackground(inputs, image_);
    if (opaque)
        run.warnings.push_back("reference: " + std::to_string(opaque) +
                               " brick segments too dense to track (extinction beyond a float, or over 2^16 collisions) taken as opaque");
}

}  // namespace voxlux
