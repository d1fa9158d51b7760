#include "lighting/extinction_sat/extinction_sat_settings.h"

#include <cmath>

#include "scene/scene_json.h"

namespace voxlux {
namespace {

AmbientOcclusion readAmbientOcclusion(const JsonObject& ao) {
    ao.rejectUnknown({"shells", "radius"});
    AmbientOcclusion a;
    a.shells = ao.integer("shells", a.shells);
    if (a.shells < 1 || a.shells > 64) ao.fail("shells", "must lie in 1..64");
    a.radius = ao.number("radius", a.radius);
    if (!(a.radius >= 0) || !std::isfinite(a.radius)) ao.fail("radius", "must be a finite distance >= 0 (0 = automatic)");
    return a;
}

ShadowCone readCone(const JsonObject& o) {
    o.rejectUnknown({"angle", "samples", "growth"});
    ShadowCone c;
    c.angle = o.number("angle", c.angle);
    if (!(c.angle >= 0 && c.angle < 60)) o.fail("angle", "must lie in [0, 60) degrees");
    c.samples = o.integer("samples", c.samples);
    if (c.samples < 1 || c.samples > 1024) o.fail("samples", "must lie in 1..1024");
    c.growth = o.number("growth", c.growth);
    if (!(c.growth >= 0 && c.growth <= 1)) o.fail("growth", "must lie in [0, 1]");
    return c;
}

}  // namespace

std::vector<std::string> ExtinctionSatSettings::keys() { return {"ambient_occlusion", "color_bleeding", "cone"}; }

void readSettings(const JsonObject& o, ExtinctionSatSettings& e) {
    if (o.has("ambient_occlusion")) e.ambient_occlusion = readOptional(o, "ambient_occlusion", readAmbientOcclusion);
    if (o.has("color_bleeding")) {
        const auto& v = o.raw("color_bleeding");
        e.color_bleeding = v.is_boolean() ? (v.get<bool>() ? 1.0f : 0.0f) : o.number("color_bleeding");
        if (!(e.color_bleeding >= 0 && e.color_bleeding <= 1))
            o.fail("color_bleeding", "must be true, false or a strength in [0, 1]");
    }
    if (o.has("cone")) e.cone = readCone(o.object("cone"));
}

void writeSettings(const ExtinctionSatSettings& s, nlohmann::json& e) {
    if (s.ambient_occlusion)
        e["ambient_occlusion"] = {{"shells", s.ambient_occlusion->shells}, {"radius", jsonDecimal(s.ambient_occlusion->radius)}};
    else
        e["ambient_occlusion"] = false;
    e["color_bleeding"] = jsonDecimal(s.color_bleeding);
    e["cone"] = {{"angle", jsonDecimal(s.cone.angle)}, {"samples", s.cone.samples}, {"growth", jsonDecimal(s.cone.growth)}};
}

}  // namespace voxlux
