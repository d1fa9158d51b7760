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

double jsonDecimal(float f) {
    char buf[32];
    for (int digits = 1; digits <= 9; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, f);
        if (std::strtof(buf, nullptr) == f) break;
    }
    return std::strtod(buf, nullptr);
}

nlohmann::json jsonVec3(glm::vec3 v) { return {jsonDecimal(v.x), jsonDecimal(v.y), jsonDecimal(v.z)}; }

namespace {

const char* pixelTypeName(PixelType t) { return t == PixelType::Float ? "float" : "half"; }


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
                step["cdl"] = {{"slope", jsonVec3(g.slope)}, {"offset", jsonVec3(g.offset)}, {"power", jsonVec3(g.power)},
                               {"saturation", jsonDecimal(g.saturation)}};
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
    nlohmann::json j = {{"grid", gridRefToJson(e.grid)}, {"intensity", jsonDecimal(e.intensity)}};
    switch (e.kind) {
        case EmissionKind::Constant:
            j["kind"] = "constant";
            j["color"] = jsonVec3(e.color);
            break;
        case EmissionKind::Ramp:
            j["kind"] = "ramp";
            for (const auto& p : e.ramp) j["ramp"].push_back({{"value", jsonDecimal(p.value)}, {"color", jsonVec3(p.color)}});
            break;
        case EmissionKind::Blackbody:
            j["kind"] = "blackbody";
            j["temperature_scale"] = jsonDecimal(e.temperature_scale);
            j["temperature_offset"] = jsonDecimal(e.temperature_offset);
            j["cutoff"] = jsonDecimal(e.cutoff);
            j["normalization"] = e.normalization == BlackbodyNormalization::Physical ? "physical" : "luminance";
            if (e.normalization == BlackbodyNormalization::Physical)
                j["reference_temperature"] = jsonDecimal(e.reference_temperature);
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
                 : l.type == LightType::Environment ? "environment"
                                                : "directional";
    if (l.type == LightType::Point || l.type == LightType::Spot) lj["position"] = jsonVec3(l.position);
    if (l.type == LightType::Directional || l.type == LightType::Spot) lj["direction"] = jsonVec3(l.direction);
    lj["color"] = jsonVec3(l.color);
    lj["intensity"] = jsonDecimal(l.intensity);
    if (l.type == LightType::Spot) {
        lj["cone_angle"] = jsonDecimal(l.cone_angle);
        lj["cone_softness"] = jsonDecimal(l.cone_softness);
    }
    if (const auto& e = l.environment) {
        lj["map"] = e->map;
        if (!e->map_colorspace.empty()) lj["map_colorspace"] = e->map_colorspace;
        if (e->up) lj["up"] = jsonVec3(*e->up);
        lj["rotation"] = jsonDecimal(e->rotation);
        lj["visible_to_camera"] = e->visible_to_camera;
        lj["median_cut_lights"] = e->median_cut_lights;
        lj["remainder"] = kEnvironmentRemainderNames[size_t(e->remainder)];
    }
    if (l.from_environment) lj["from_environment"] = *l.from_environment;
    if (!l.group.empty()) lj["group"] = l.group;
    if (l.volumes) lj["volumes"] = *l.volumes;
    if (l.shadow_volumes) lj["shadow_volumes"] = *l.shadow_volumes;
    return lj;
}

namespace {

nlohmann::json poseToJson(const TransformKey& k) {
    return {{"translate", jsonVec3(k.translate)}, {"rotate", jsonVec3(k.rotate)}, {"scale", jsonVec3(k.scale)}};
}

}  // namespace

// As written: a .chan file stays a file name, so an edit of the file is not an edit of the scene
// text (the render graph hashes the file's identity beside it).
nlohmann::json matrixToJson(const glm::mat4& m) {
    nlohmann::json out = nlohmann::json::array();
    for (int i = 0; i < 16; ++i) out.push_back(jsonDecimal(m[i / 4][i % 4]));
    return out;
}

glm::mat4 matrixFromJson(const nlohmann::json& j) {
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = j.at(size_t(i)).get<float>();
    return m;
}

nlohmann::json volumeTransformToJson(const VolumeTransform& t) {
    if (t.matrix) return {{"matrix", matrixToJson(*t.matrix)}};
    nlohmann::json j;
    if (!t.chan.empty()) {   // the file gives translate and rotate per frame; scale applies to all
        j = {{"chan", t.chan}, {"scale", jsonVec3(t.scale)}};
    } else if (!t.keys.empty()) {
        for (const TransformKey& k : t.keys) {
            nlohmann::json key = poseToJson(k);
            key["frame"] = k.frame;
            j["keys"].push_back(key);
        }
    } else {
        j = poseToJson({0.0, t.translate, t.rotate, t.scale});
    }
    if (t.rotate_order != RotateOrder::Xyz) j["rotate_order"] = kRotateOrderNames[int(t.rotate_order)];
    return j;
}

namespace {

nlohmann::json materialToJson(const Material& material) {
    nlohmann::json m;
    m["density_scale"] = jsonDecimal(material.density_scale);
    m["density_units"] = material.density_units == DensityUnits::Voxel ? "voxel" : "world";
    m["albedo"] = jsonVec3(material.albedo);
    m["anisotropy"] = jsonDecimal(material.anisotropy);
    for (const auto& p : material.transfer)
        m["transfer_function"].push_back({{"value", jsonDecimal(p.value)}, {"extinction", jsonDecimal(p.extinction)}, {"albedo", jsonVec3(p.albedo)}});
    for (const auto& r : material.transfer_2d) {
        nlohmann::json region = {{"fade", jsonDecimal(r.fade)}, {"extinction", jsonDecimal(r.extinction)}, {"albedo", jsonVec3(r.albedo)}};
        if (!r.name.empty()) region["name"] = r.name;
        if (r.transport) region["transport"] = jsonVec3(*r.transport);
        if (r.surface) region["surface"] = jsonDecimal(*r.surface);
        const auto pair = [](glm::vec2 p) { return nlohmann::json::array({jsonDecimal(p.x), jsonDecimal(p.y)}); };
        if (r.triangle) {
            region["triangle"] = {pair(r.corners[0]), pair(r.corners[1]), pair(r.corners[2])};
        } else {
            region["value"] = pair(r.value);
            if (r.gradient != glm::vec2(0.0f, kAnyGradient)) region["gradient"] = pair(r.gradient);
        }
        m["transfer_function_2d"].push_back(region);
    }
    return m;
}

nlohmann::json volumeToJson(const VolumeSpec& volume) {
    nlohmann::json v;
    if (!volume.name.empty()) v["name"] = volume.name;   // unset in a scene built in code: the reader names it
    v["path"] = volume.path;
    if (volume.frames) {
        if (volume.frames->isRange()) v["frames"] = {volume.frames->first(), volume.frames->last()};
        else v["frames"] = volume.frames->text();
    }
    v["density"] = gridRefToJson(volume.density);
    if (volume.color) v["color"] = gridRefToJson(*volume.color);
    v["level_set"] = volume.level_set == LevelSetPolicy::ConvertToFog ? "fog" : "reject";
    v["up"] = upAxisName(volume.up);
    // Written only when set: a scene without one hashes as it did before the key existed.
    if (const auto& t = volume.transform) v["transform"] = volumeTransformToJson(*t);
    if (volume.holdout_mesh) v["holdout_mesh"] = *volume.holdout_mesh;   // a render document's, never a scene file's
    for (const VolumeTransform& t : volume.instances) v["instances"].push_back(volumeTransformToJson(t));
    v["role"] = kVolumeRoleNames[size_t(volume.role)];
    if (!volume.enabled) v["enabled"] = false;   // written only when off, as a render's scene has none off
    v["material"] = materialToJson(volume.material);
    v["emission"] = nlohmann::json::array();
    for (const auto& e : volume.emission) v["emission"].push_back(emissionToJson(e));
    return v;
}

}  // namespace

nlohmann::json sceneToJson(const Scene& s) {
    nlohmann::json j;
    j["volumes"] = nlohmann::json::array();
    for (const VolumeSpec& v : s.volumes) j["volumes"].push_back(volumeToJson(v));

    j["lights"] = nlohmann::json::array();
    for (const auto& l : s.lights) j["lights"].push_back(lightToJson(l));
    if (!s.holdouts.empty()) {
        j["holdouts"] = nlohmann::json::array();
        for (const Holdout& h : s.holdouts) {
            if (h.mesh.empty()) {
                j["holdouts"].push_back({{"depth", h.depth}, {"channel", h.channel}, {"ray_distance", h.ray_distance}});
                continue;
            }
            nlohmann::json& m = j["holdouts"].emplace_back(nlohmann::json{{"mesh", h.mesh}, {"voxel_size", jsonDecimal(h.voxel_size)}});
            if (h.transform) m["transform"] = volumeTransformToJson(*h.transform);
            if (h.shadow_reach) m["shadow_reach"] = jsonDecimal(*h.shadow_reach);
        }
    }

    if (s.camera) {
        auto& c = j["camera"];
        const bool lens_in_file = s.camera->file && !s.camera->file->vertical_fov.empty();
        if (s.camera->focal_length > 0.0f) {
            c["focal_length"] = jsonDecimal(s.camera->focal_length);
            c["film_back"] = {jsonDecimal(s.camera->film_back.x), jsonDecimal(s.camera->film_back.y)};
        } else if (!lens_in_file) {
            c["fov"] = jsonDecimal(s.camera->fov);
        }
        if (const auto& f = s.camera->file) {   // as written: the file stays a file name
            c["file"] = f->path;
            if (!f->pose.keys.empty()) c["rotate_order"] = kRotateOrderNames[int(f->pose.rotate_order)];
            else c["name"] = f->name;
        } else if (s.camera->matrix) {
            c["matrix"] = matrixToJson(*s.camera->matrix);
        } else {
            c["position"] = jsonVec3(s.camera->position);
            c["look_at"] = jsonVec3(s.camera->look_at);
            c["up"] = jsonVec3(s.camera->up);
        }
        if (s.camera->motion)
            c["motion"] = {{"open", {{"matrix", matrixToJson((*s.camera->motion)[0])}}},
                           {"close", {{"matrix", matrixToJson((*s.camera->motion)[1])}}}};
        if (s.camera->fstop > 0.0f) {
            c["fstop"] = jsonDecimal(s.camera->fstop);
            c["focus_distance"] = jsonDecimal(s.camera->focus_distance);
            c["world_unit_mm"] = jsonDecimal(s.camera->world_unit_mm);
            c["lens_samples"] = s.camera->lens_samples;
        }
    }

    auto& r = j["render"];
    r["resolution"] = {s.render.width, s.render.height};
    r["step"] = jsonDecimal(s.render.step);
    r["shadow_step"] = jsonDecimal(s.render.shadow_step);
    r["transmittance_cutoff"] = jsonDecimal(s.render.transmittance_cutoff);
    r["exposure"] = jsonDecimal(s.render.exposure);
    r["filter"] = s.render.filter == Filter::Tricubic ? "tricubic" : "trilinear";
    r["backend"] = s.render.backend == Backend::Cpu ? "cpu" : s.render.backend == Backend::Gl ? "gl" : "auto";
    r["method"] = s.render.method == RenderMethod::Reference ? "reference" : "march";
    const ReferenceSettings& ref = s.render.reference;
    r["reference"] = {{"spp", ref.spp}, {"max_bounces", ref.max_bounces}, {"seed", ref.seed}, {"roulette_depth", ref.roulette_depth}};
    if (const auto& mb = s.render.motion_blur) {
        r["motion_blur"] = {{"shutter", {jsonDecimal(mb->shutter_open), jsonDecimal(mb->shutter_close)}}, {"velocity_scale", jsonDecimal(mb->velocity_scale)},
                            {"fps", jsonDecimal(mb->fps)}, {"samples", mb->samples}};
        if (mb->velocity) r["motion_blur"]["velocity"] = gridRefToJson(*mb->velocity);
    } else {
        r["motion_blur"] = false;
    }
    // Written only when set: a scene without one hashes as it did before the key existed.
    if (const auto& b = s.render.region) r["region"] = {jsonDecimal((*b)[0]), jsonDecimal((*b)[1]), jsonDecimal((*b)[2]), jsonDecimal((*b)[3])};

    auto& e = j["effects"];
    e["shadows"] = shadowMethodName(s.effects.shadows);
    writeMethodSettings(s.effects, e);
    if (const auto& sf = s.effects.surface)
        e["surface"] = {{"gradient_low", jsonDecimal(sf->gradient_low)}, {"gradient_high", jsonDecimal(sf->gradient_high)},
                        {"specular", jsonDecimal(sf->specular)}, {"shininess", jsonDecimal(sf->shininess)}};
    else
        e["surface"] = false;
    if (const auto& p = s.effects.perturbation)
        e["perturbation"] = {{"seed", p->seed}, {"scale", jsonDecimal(p->scale)}, {"octaves", p->octaves},
                             {"lacunarity", jsonDecimal(p->lacunarity)}, {"gain", jsonDecimal(p->gain)},
                             {"density", jsonDecimal(p->density)}, {"transport", jsonDecimal(p->transport)},
                             {"displacement", jsonDecimal(p->displacement)}, {"velocity", jsonVec3(p->velocity)},
                             {"time", jsonDecimal(p->time)}};
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
    for (VolumeSpec& v : scene.volumes) {
        relative(v.path);
        if (v.transform) relative(v.transform->chan);
    }
    relative(scene.color.config);
    for (Holdout& h : scene.holdouts) {
        relative(h.depth);
        relative(h.mesh);
        if (h.transform) relative(h.transform->chan);
    }
    if (scene.camera && scene.camera->file) relative(scene.camera->file->path);
    for (Light& l : scene.lights)
        if (l.environment) relative(l.environment->map);
    for (GradeStep& g : scene.color.grade) relative(g.file);
    return scene;
}

}  // namespace voxlux
