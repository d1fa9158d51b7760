#include "lighting/propagation/propagation_settings.h"

#include <cmath>
#include <string>

#include "kernel/kernel_types.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace {

Propagation readPropagation(const JsonObject& o) {
    o.rejectUnknown({"blend_axes", "eye_pass", "chroma_subsampling", "coherent", "filter"});
    Propagation p;
    p.coherent = o.boolean("coherent", p.coherent);
    p.blend_axes = o.boolean("blend_axes", p.blend_axes);
    p.eye_pass = o.boolean("eye_pass", p.eye_pass);
    p.chroma_subsampling = o.boolean("chroma_subsampling", p.chroma_subsampling);
    p.filter = o.choice("filter", {"trilinear", "tricubic"}, "tricubic") == "tricubic" ? Filter::Tricubic : Filter::Trilinear;
    return p;
}

Indirect readIndirect(const JsonObject& o) {
    o.rejectUnknown({"model", "strength", "angle", "samples", "phase", "exponent", "g", "transport_color"});
    Indirect in;
    // A transport colour is Kniss's parameter: giving one picks his model unless "model" says otherwise.
    const std::string implied = o.has("transport_color") ? "kniss" : "diffusion";
    in.model = o.choice("model", {"diffusion", "kniss"}, implied) == "kniss" ? IndirectModel::Kniss : IndirectModel::Diffusion;
    if (in.model == IndirectModel::Diffusion && o.has("transport_color"))
        o.fail("transport_color", "is the kniss model's; the diffusion model derives it from material.albedo and anisotropy");
    in.strength = o.number("strength", in.strength);
    if (!(in.strength >= 0) || !std::isfinite(in.strength)) o.fail("strength", "must be a finite value >= 0");
    in.angle = o.number("angle", in.angle);
    if (!(in.angle >= 0 && in.angle <= 90)) o.fail("angle", "must lie in [0, 90] degrees");
    in.samples = o.integer("samples", in.samples);
    if (in.samples < 1 || in.samples > VX_MAX_TAPS) o.fail("samples", "must lie in 1.." + std::to_string(VX_MAX_TAPS));
    in.phase = o.choice("phase", {"phong", "henyey_greenstein"}, "phong") == "phong" ? BlurPhase::Phong
                                                                                    : BlurPhase::HenyeyGreenstein;
    in.exponent = o.number("exponent", in.exponent);
    if (!(in.exponent >= 0 && in.exponent <= 1000)) o.fail("exponent", "must lie in [0, 1000]");
    in.g = o.number("g", in.g);
    if (!(in.g > -1 && in.g < 1)) o.fail("g", "must lie in (-1, 1)");
    in.transport_color = o.vec3("transport_color", in.transport_color);
    if (glm::any(glm::lessThanEqual(in.transport_color, glm::vec3(0))) ||
        glm::any(glm::greaterThan(in.transport_color, glm::vec3(1))))
        o.fail("transport_color", "each component must lie in (0, 1]");
    return in;
}

}  // namespace

std::vector<std::string> PropagationSettings::keys() { return {"propagation", "indirect"}; }

void readSettings(const JsonObject& o, PropagationSettings& e) {
    if (o.has("propagation")) e.propagation = readPropagation(o.object("propagation"));
    if (o.has("indirect")) e.indirect = readOptional(o, "indirect", readIndirect);
}

void writeSettings(const PropagationSettings& s, nlohmann::json& e) {
    const Propagation& pr = s.propagation;
    e["propagation"] = {{"blend_axes", pr.blend_axes}, {"eye_pass", pr.eye_pass}, {"chroma_subsampling", pr.chroma_subsampling},
                        {"coherent", pr.coherent}, {"filter", pr.filter == Filter::Tricubic ? "tricubic" : "trilinear"}};
    if (const auto& in = s.indirect) {
        const bool kniss = in->model == IndirectModel::Kniss;
        e["indirect"] = {{"model", kniss ? "kniss" : "diffusion"}, {"strength", jsonDecimal(in->strength)}, {"angle", jsonDecimal(in->angle)},
                         {"samples", in->samples}, {"phase", in->phase == BlurPhase::Phong ? "phong" : "henyey_greenstein"},
                         {"exponent", jsonDecimal(in->exponent)}, {"g", jsonDecimal(in->g)}};
        if (kniss) e["indirect"]["transport_color"] = jsonVec3(in->transport_color);
    } else
        e["indirect"] = false;
}

}  // namespace voxlux
