#include "render_plan.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace voxlux {

namespace {

bool hasLight(const Scene& s, bool ambient) {
    return std::any_of(s.lights.begin(), s.lights.end(),
                       [&](const Light& l) { return l.enabled && (l.type == LightType::Ambient) == ambient; });
}

// Why the light-cache stage runs (which passes), or why it is skipped.
std::string lightCacheReason(const Scene& s) {
    const Effects& fx = s.effects;
    std::vector<std::string> passes, idle;
    if (needsAmbientOcclusion(s))
        passes.push_back("ambient occlusion, " + std::to_string(fx.ambient_occlusion->shells) + " shells" +
                         (fx.color_bleeding > 0 ? " with colour bleeding" : ""));
    else if (fx.ambient_occlusion)
        idle.push_back("ambient_occlusion is on but no ambient light is in the scene");
    if (needsConeShadows(s)) {
        size_t lights = 0;
        for (const auto& l : s.lights) lights += l.enabled && l.type != LightType::Ambient;
        char cone[96];
        std::snprintf(cone, sizeof cone, "%zu shadow cone%s of %d cuboids (%g deg)", lights, lights == 1 ? "" : "s",
                      fx.cone.samples, double(fx.cone.angle));
        passes.push_back(cone);
    }
    if (fx.color_bleeding > 0 && !needsAmbientOcclusion(s)) idle.push_back("color_bleeding needs ambient occlusion");
    std::string out;
    if (passes.empty()) {
        out = "skipped: no effect in the scene needs a precomputed light cache";
    } else {
        out = "extinction SAT over a " + std::to_string(fx.light_resolution) + "-cell light grid; ";
        for (size_t i = 0; i < passes.size(); ++i) out += (i ? ", " : "") + passes[i];
    }
    for (const auto& why : idle) out += " (" + why + ")";
    return out;
}

// Why the illumination stage runs (which sweeps), or why it is skipped.
std::string illuminationReason(const Scene& s) {
    const Effects& fx = s.effects;
    if (!needsPropagation(s)) {
        std::string out = "skipped: no effect in the scene needs an illumination volume";
        if (fx.shadows == ShadowMethod::Propagation) out += " (propagation shadows but no light to propagate)";
        else if (fx.indirect) out += " (indirect light needs effects.shadows = propagation)";
        return out;
    }
    size_t lights = 0;
    for (const auto& l : s.lights) lights += l.enabled && l.type != LightType::Ambient;
    std::string out = std::to_string(lights) + (lights == 1 ? " light" : " lights") + " swept through a " +
                      std::to_string(fx.light_resolution) + "-cell illumination volume along " +
                      (fx.propagation.blend_axes ? "the two closest axes, blended" : "the closest axis") +
                      (lights > 1 ? (fx.propagation.coherent ? ", one pass per direction" : ", one pass per light") : "") +
                      "; direct RGB";
    if (const auto& in = fx.indirect) {
        char blur[160];
        std::snprintf(blur, sizeof blur, ", indirect RGB blurred in a %g deg cone over %d taps, transport colour (%g, %g, %g)",
                      double(in->angle), in->samples, double(in->transport_color.x), double(in->transport_color.y),
                      double(in->transport_color.z));
        out += blur;
        if (fx.propagation.chroma_subsampling) out += ", chroma subsampled 2x";
        if (fx.propagation.eye_pass) out += ", eye pass";
    }
    if (fx.perturbation) out += ", perturbed";
    return out;
}

// What the grade stage does, or why it is skipped. Names are as the scene gives them; the
// config resolves them (and reports missing ones) before the render starts.
std::string gradeReason(const Scene& s) {
    const ColorSettings& c = s.color;
    const std::string working = c.working_space.empty() ? "the scene_linear role" : c.working_space;
    if (!needsGrade(s)) return "skipped: no grade, output in the working space (" + working + "), no preview";
    std::string steps;
    for (const auto& g : c.grade) {
        std::string step = g.kind == GradeKind::Look  ? "look '" + g.look + "'"
                           : g.kind == GradeKind::Cdl ? std::string("CDL")
                                                      : "'" + std::filesystem::path(g.file).filename().string() + "'";
        if (!g.space.empty()) step += " in " + g.space;
        if (g.inverse) step += " (inverse)";
        steps += steps.empty() ? "grade " : ", ";
        steps += step;
    }
    std::vector<std::string> parts;
    if (!steps.empty()) parts.push_back(steps + (c.unpremultiply ? " on unpremultiplied colour" : ""));
    if (!c.output_space.empty() && c.output_space != c.working_space) parts.push_back(working + " -> " + c.output_space);
    if (!s.output.preview.empty())
        parts.push_back("preview through " + (c.display.empty() ? std::string("the default display") : "'" + c.display + "'") +
                        (c.view.empty() ? "" : " / '" + c.view + "'"));
    std::string out;
    for (const auto& p : parts) {
        if (!out.empty()) out += "; ";
        out += p;
    }
    return out;
}

std::string shadowDescription(ShadowMethod m) {
    switch (m) {
        case ShadowMethod::Raymarch: return "ray-marched shadow rays per sample (reference)";
        case ShadowMethod::SatCone: return "SAT-cone shadows read from the light cache";
        case ShadowMethod::Propagation: return "direct and indirect light read from the illumination volume";
        case ShadowMethod::None: break;
    }
    return "unshadowed (effects.shadows = none)";
}

std::string emissionDescription(const EmissionSource& e) {
    const char* kind = e.kind == EmissionKind::Blackbody ? "blackbody" : e.kind == EmissionKind::Ramp ? "ramp" : "constant";
    return std::string(kind) + " from '" + e.grid.name + "'";
}

}  // namespace

bool needsAmbientOcclusion(const Scene& s) { return s.effects.ambient_occlusion && hasLight(s, true); }
bool needsConeShadows(const Scene& s) { return s.effects.shadows == ShadowMethod::SatCone && hasLight(s, false); }
bool needsPropagation(const Scene& s) { return s.effects.shadows == ShadowMethod::Propagation && hasLight(s, false); }
bool needsGrade(const Scene& s) {
    const ColorSettings& c = s.color;
    return !c.grade.empty() || (!c.output_space.empty() && c.output_space != c.working_space) || !s.output.preview.empty();
}

std::vector<PlannedStage> planRender(const Scene& s) {
    std::vector<PlannedStage> plan;
    std::string grids = "density '" + s.volume.density.name + "'";
    if (s.volume.color) grids += ", colour '" + s.volume.color->name + "'";
    for (size_t i = 0; i < s.emission.size(); ++i) {
        grids += i ? ", '" : ", emission '";
        grids += s.emission[i].grid.name + "'";
    }
    plan.push_back({"load", {"volume", "emission"}, true, "reads " + grids + " from " + s.volume.path});
    plan.push_back({"brick", {"load"}, true, "densifies active voxels into 8^3 bricks with a +1 apron"});
    plan.push_back({"classify", {"brick", "material", "emission"}, true,
                    s.material.transfer.empty() ? "drops bricks with zero density and emission"
                                                : "drops bricks the transfer function makes transparent"});
    // The reference traces every shadow ray and bounce itself: precomputed light would bias it.
    const bool reference = s.render.method == RenderMethod::Reference;
    const std::string by_reference = "skipped: the Monte Carlo reference (render.method) computes all light itself";
    plan.push_back({"light_cache", {"classify", "lights", "effects"}, !reference && (needsAmbientOcclusion(s) || needsConeShadows(s)),
                    reference ? by_reference : lightCacheReason(s)});
    plan.push_back({"illumination", {"classify", "lights", "effects", "camera"}, !reference && needsPropagation(s),
                    reference ? by_reference : illuminationReason(s)});

    std::string march;
    if (reference) {
        const ReferenceSettings& ref = s.render.reference;
        march = "Monte Carlo reference: delta tracking, ratio-tracked shadows, up to " + std::to_string(ref.max_bounces) +
                (ref.max_bounces == 1 ? " bounce, " : " bounces, ") + std::to_string(ref.spp) + " spp";
    } else if (s.lights.empty()) {
        march = "no lights: emission and transmittance only";
    } else {
        march = std::to_string(s.lights.size()) + (s.lights.size() == 1 ? " light, " : " lights, ");
        march += hasLight(s, false) ? shadowDescription(s.effects.shadows) : "ambient only";
        if (hasLight(s, true)) march += needsAmbientOcclusion(s) ? ", occluded ambient" : ", unoccluded ambient";
    }
    if (s.effects.surface && !reference) march += ", surface shading where the gradient is steep";
    if (s.effects.perturbation && !reference) march += ", noise-perturbed";
    for (size_t i = 0; i < s.emission.size(); ++i) {
        march += i ? ", " : ", emission: ";
        march += emissionDescription(s.emission[i]);
    }
    plan.push_back({"march", {"classify", "light_cache", "illumination", "camera", "lights", "render", "emission"}, true, march});
    plan.push_back({"grade", {"march", "color", "output"}, needsGrade(s), gradeReason(s)});
    plan.push_back({"write", {"march", "grade", "output"}, true,
                    "EXR, " + std::string(s.output.pixel_type == PixelType::Half ? "half" : "float") + ", " +
                        s.output.compression + (s.output.aovs.empty() ? "" : ", AOVs") +
                        (s.output.preview.empty() ? "" : ", and an 8-bit PNG preview")});
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
        for (size_t pad = st.name.size(); pad < 12 || pad == st.name.size(); ++pad) out << ' ';
        out << st.reason << "  [in:";
        for (const auto& i : st.inputs) out << ' ' << i;
        out << "]\n";
    }
    return out.str();
}

}  // namespace voxlux
