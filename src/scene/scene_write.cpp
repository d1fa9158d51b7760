// Scene -> JSON, as `voxlux scene` writes it and as the render graph hashes it (every value the
// renderer reads, floats as the shortest decimal that reads back to the same float).
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "scene/scene_json.h"

namespace voxlux {
namespace {

nlohmann::json gridRefToJson(const GridRef& g) {
    if (g.index == 0) return g.name;
    return {{"name", g.name}, {"index", g.index}};
}

}  // namespace

const char* upAxisName(UpAxis up) {
    return up == UpAxis::X ? "x" : up == UpAxis::Y ? "y" : up == UpAxis::Z ? "z" : "auto";
}

namespace {

const char* pixelTypeName(PixelType t) { return t == PixelType::Float ? "float" : "half"; }

// Floats as the shortest decimal that reads back to the same float (0.9f prints as 0.9).
double decimal(float f) {
    char buf[32];
    for (int digits = 1; digits <= 9; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, f);
        if (std::strtof(buf, nullptr) == f) break;
    }
    return std::strtod(buf, nullptr);
}

nlohmann::json vec(glm::vec3 v) { return {decimal(v.x), decimal(v.y), decimal(v.z)}; }

// Column-major, as camera.matrix reads it.
nlohmann::json matrixToJson(const glm::mat4& m) {
    nlohmann::json out = nlohmann::json::array();
    for (int i = 0; i < 16; ++i) out.push_back(decimal(m[i / 4][i % 4]));
    return out;
}

nlohmann::json colorToJson(const ColorSettings& c) {
    nlohmann::json j = nlohmann::json::object();
    if (!c.config.empty()) j["config"] = c.config;
    if (!c.working_space.empty()) j["working_space"] = c.working_space;
    if (!c.output_space.empty()) j["output_space"] = c.output_space;
    for (const auto& g : c.grade) {
        nlohmann::json step;
        switch (g.kind) {
            case GradeKind::Look: step["look"] = g.look; break;
            case GradeKind::Cdl:
                step["cdl"] = {{"slope", vec(g.slope)}, {"offset", vec(g.offset)}, {"power", vec(g.power)},
                               {"saturation", decimal(g.saturation)}};
                break;
            case GradeKind::CdlFile:
                step["cdl_file"] = g.file;
                if (!g.cccid.empty()) step["cccid"] = g.cccid;
                break;
            case GradeKind::Lut:
                step["lut"] = g.file;
                step["interpolation"] = g.interpolation;
                break;
        }
        if (!g.space.empty()) step["space"] = g.space;
        if (g.inverse) step["inverse"] = true;
        if (g.clamp) step["clamp"] = true;
        j["grade"].push_back(step);
    }
    if (!c.unpremultiply) j["unpremultiply"] = false;
    if (!c.display.empty()) j["display"] = c.display;
    if (!c.view.empty()) j["view"] = c.view;
    return j;
}

nlohmann::json emissionToJson(const EmissionSource& e) {
    nlohmann::json j = {{"grid", gridRefToJson(e.grid)}, {"intensity", decimal(e.intensity)}};
    switch (e.kind) {
        case EmissionKind::Constant:
            j["kind"] = "constant";
            j["color"] = vec(e.color);
            break;
        case EmissionKind::Ramp:
            j["kind"] = "ramp";
            for (const auto& p : e.ramp) j["ramp"].push_back({{"value", decimal(p.value)}, {"color", vec(p.color)}});
            break;
        case EmissionKind::Blackbody:
            j["kind"] = "blackbody";
            j["temperature_scale"] = decimal(e.temperature_scale);
            j["temperature_offset"] = decimal(e.temperature_offset);
            j["cutoff"] = decimal(e.cutoff);
            j["normalization"] = e.normalization == BlackbodyNormalization::Physical ? "physical" : "luminance";
            if (e.normalization == BlackbodyNormalization::Physical)
                j["reference_temperature"] = decimal(e.reference_temperature);
            break;
    }
    return j;
}

}  // namespace

nlohmann::json lightToJson(const Light& l) {
    nlohmann::json lj;
    if (!l.name.empty()) lj["name"] = l.name;
    if (!l.enabled) lj["enabled"] = false;
    lj["type"] = l.type == LightType::Point     ? "point"
                 : l.type == LightType::Spot    ? "spot"
                 : l.type == LightType::Ambient ? "ambient"
                                                : "directional";
    if (l.type == LightType::Point || l.type == LightType::Spot) lj["position"] = vec(l.position);
    if (l.type == LightType::Directional || l.type == LightType::Spot) lj["direction"] = vec(l.direction);
    lj["color"] = vec(l.color);
    lj["intensity"] = decimal(l.intensity);
    if (l.type == LightType::Spot) {
        lj["cone_angle"] = decimal(l.cone_angle);
        lj["cone_softness"] = decimal(l.cone_softness);
    }
    return lj;
}

nlohmann::json sceneToJson(const Scene& s) {
    nlohmann::json j;
    auto& v = j["volume"];
    v["path"] = s.volume.path;
    if (s.volume.frames) {
        if (s.volume.frames->isRange()) v["frames"] = {s.volume.frames->first(), s.volume.frames->last()};
        else v["frames"] = s.volume.frames->text();
    }
    v["density"] = gridRefToJson(s.volume.density);
    if (s.volume.color) v["color"] = gridRefToJson(*s.volume.color);
    v["level_set"] = s.volume.level_set == LevelSetPolicy::ConvertToFog ? "fog" : "reject";
    v["up"] = upAxisName(s.volume.up);

    auto& m = j["material"];
    m["density_scale"] = decimal(s.material.density_scale);
    m["density_units"] = s.material.density_units == DensityUnits::Voxel ? "voxel" : "world";
    m["albedo"] = vec(s.material.albedo);
    m["anisotropy"] = decimal(s.material.anisotropy);
    for (const auto& p : s.material.transfer)
        m["transfer_function"].push_back({{"value", decimal(p.value)}, {"extinction", decimal(p.extinction)}, {"albedo", vec(p.albedo)}});
    for (const auto& r : s.material.transfer_2d) {
        nlohmann::json region = {{"fade", decimal(r.fade)}, {"extinction", decimal(r.extinction)}, {"albedo", vec(r.albedo)}};
        if (!r.name.empty()) region["name"] = r.name;
        if (r.transport) region["transport"] = vec(*r.transport);
        if (r.surface) region["surface"] = decimal(*r.surface);
        const auto pair = [](glm::vec2 p) { return nlohmann::json::array({decimal(p.x), decimal(p.y)}); };
        if (r.triangle) {
            region["triangle"] = {pair(r.corners[0]), pair(r.corners[1]), pair(r.corners[2])};
        } else {
            region["value"] = pair(r.value);
            if (r.gradient != glm::vec2(0.0f, kAnyGradient)) region["gradient"] = pair(r.gradient);
        }
        m["transfer_function_2d"].push_back(region);
    }

    j["lights"] = nlohmann::json::array();
    for (const auto& l : s.lights) j["lights"].push_back(lightToJson(l));

    j["emission"] = nlohmann::json::array();
    for (const auto& e : s.emission) j["emission"].push_back(emissionToJson(e));

    if (s.camera) {
        auto& c = j["camera"];
        c["fov"] = decimal(s.camera->fov);
        if (s.camera->matrix) {
            c["matrix"] = matrixToJson(*s.camera->matrix);
        } else {
            c["position"] = vec(s.camera->position);
            c["look_at"] = vec(s.camera->look_at);
            c["up"] = vec(s.camera->up);
        }
        if (s.camera->motion)
            c["motion"] = {{"open", {{"matrix", matrixToJson((*s.camera->motion)[0])}}},
                           {"close", {{"matrix", matrixToJson((*s.camera->motion)[1])}}}};
    }

    auto& r = j["render"];
    r["resolution"] = {s.render.width, s.render.height};
    r["step"] = decimal(s.render.step);
    r["shadow_step"] = decimal(s.render.shadow_step);
    r["transmittance_cutoff"] = decimal(s.render.transmittance_cutoff);
    r["exposure"] = decimal(s.render.exposure);
    r["filter"] = s.render.filter == Filter::Tricubic ? "tricubic" : "trilinear";
    r["backend"] = s.render.backend == Backend::Cpu ? "cpu" : s.render.backend == Backend::Gl ? "gl" : "auto";
    r["method"] = s.render.method == RenderMethod::Reference ? "reference" : "march";
    const ReferenceSettings& ref = s.render.reference;
    r["reference"] = {{"spp", ref.spp}, {"max_bounces", ref.max_bounces}, {"seed", ref.seed}, {"roulette_depth", ref.roulette_depth}};
    if (const auto& mb = s.render.motion_blur) {
        r["motion_blur"] = {{"shutter", {decimal(mb->shutter_open), decimal(mb->shutter_close)}}, {"velocity_scale", decimal(mb->velocity_scale)},
                            {"fps", decimal(mb->fps)}, {"samples", mb->samples}};
        if (mb->velocity) r["motion_blur"]["velocity"] = gridRefToJson(*mb->velocity);
    } else {
        r["motion_blur"] = false;
    }
    // Written only when set: a scene without one hashes as it did before the key existed.
    if (const auto& b = s.render.region) r["region"] = {decimal((*b)[0]), decimal((*b)[1]), decimal((*b)[2]), decimal((*b)[3])};

    auto& e = j["effects"];
    e["shadows"] = shadowMethodName(s.effects.shadows);
    if (s.effects.ambient_occlusion)
        e["ambient_occlusion"] = {{"shells", s.effects.ambient_occlusion->shells},
                                  {"radius", decimal(s.effects.ambient_occlusion->radius)}};
    else
        e["ambient_occlusion"] = false;
    e["color_bleeding"] = decimal(s.effects.color_bleeding);
    e["cone"] = {{"angle", decimal(s.effects.cone.angle)}, {"samples", s.effects.cone.samples},
                 {"growth", decimal(s.effects.cone.growth)}};
    const Propagation& pr = s.effects.propagation;
    e["propagation"] = {{"blend_axes", pr.blend_axes}, {"eye_pass", pr.eye_pass}, {"chroma_subsampling", pr.chroma_subsampling}, {"coherent", pr.coherent},
                         {"filter", pr.filter == Filter::Tricubic ? "tricubic" : "trilinear"}};
    if (const auto& in = s.effects.indirect) {
        const bool kniss = in->model == IndirectModel::Kniss;
        e["indirect"] = {{"model", kniss ? "kniss" : "diffusion"}, {"strength", decimal(in->strength)}, {"angle", decimal(in->angle)},
                         {"samples", in->samples}, {"phase", in->phase == BlurPhase::Phong ? "phong" : "henyey_greenstein"},
                         {"exponent", decimal(in->exponent)}, {"g", decimal(in->g)}};
        if (kniss) e["indirect"]["transport_color"] = vec(in->transport_color);
    } else
        e["indirect"] = false;
    if (const auto& sf = s.effects.surface)
        e["surface"] = {{"gradient_low", decimal(sf->gradient_low)}, {"gradient_high", decimal(sf->gradient_high)},
                        {"specular", decimal(sf->specular)}, {"shininess", decimal(sf->shininess)}};
    else
        e["surface"] = false;
    if (const auto& p = s.effects.perturbation)
        e["perturbation"] = {{"seed", p->seed}, {"scale", decimal(p->scale)}, {"octaves", p->octaves},
                             {"lacunarity", decimal(p->lacunarity)}, {"gain", decimal(p->gain)},
                             {"density", decimal(p->density)}, {"transport", decimal(p->transport)},
                             {"displacement", decimal(p->displacement)}, {"velocity", vec(p->velocity)},
                             {"time", decimal(p->time)}};
    else
        e["perturbation"] = false;
    e["light_resolution"] = s.effects.light_resolution;
    e["light_memory_mb"] = s.effects.light_memory_mb;

    j["color"] = colorToJson(s.color);

    auto& o = j["output"];
    if (!s.output.path.empty()) o["path"] = s.output.path;
    if (!s.output.preview.empty()) o["preview"] = s.output.preview;
    o["pixel_type"] = pixelTypeName(s.output.pixel_type);
    o["compression"] = s.output.compression;
    o["deep"] = s.output.deep;
    o["deep_samples"] = s.output.deep_samples;
    o["aovs"] = nlohmann::json::array();
    for (const AovSpec& a : s.output.aovs)
        o["aovs"].push_back(a.pixel_type ? nlohmann::json{{"name", a.name}, {"pixel_type", pixelTypeName(*a.pixel_type)}}
                                         : nlohmann::json(a.name));
    return j;
}

Scene scenePathsRelativeTo(Scene scene, const std::string& folder) {
    const auto base = std::filesystem::absolute(folder);
    const auto relative = [&](std::string& path) {
        if (!path.empty()) path = std::filesystem::absolute(path).lexically_normal().lexically_relative(base).string();
    };
    relative(scene.volume.path);
    relative(scene.color.config);
    for (GradeStep& g : scene.color.grade) relative(g.file);
    return scene;
}

}  // namespace voxlux
