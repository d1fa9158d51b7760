// JSON -> Scene: reads and validates a scene file (docs/scene.md). Every bad key is an InputError
// naming the file and the key's JSON pointer; relative paths are resolved against the file's folder.
#include "scene/scene_json.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include <glm/gtx/component_wise.hpp>

#include "optics/emission.h"
#include "optics/transfer_presets.h"
#include "core/error.h"
#include "core/frame_pattern.h"
#include "core/json_reader.h"
#include "kernel/kernel_types.h"
#include "scene/camera.h"
#include "scene/camera_file.h"
#include "scene/chan_file.h"
#include "scene/mesh_file.h"

namespace voxlux {
namespace fs = std::filesystem;

namespace {

GridRef readGridRef(const JsonObject& parent, const std::string& key) {
    const auto& v = parent.raw(key);
    if (v.is_string()) return {v.get<std::string>(), 0};
    JsonObject o = parent.object(key);
    o.rejectUnknown({"name", "index"});
    GridRef ref{o.string("name"), o.integer("index", 0)};
    if (ref.index < 0) o.fail("index", "must be 0 or more");
    return ref;
}

// Paths in a scene file are relative to its folder.
std::string resolvePath(const std::string& path, const std::string& base_dir) {
    if (fs::path(path).is_relative() && !base_dir.empty()) return (fs::path(base_dir) / path).lexically_normal().string();
    return path;
}

// A region of material.transfer_function_2d: a rectangle ("value" and "gradient" ranges) or a
// triangle ("triangle": three [value, gradient] corners).
TransferRegion readTransferRegion(const JsonObject& o) {
    o.rejectUnknown({"name", "value", "gradient", "triangle", "fade", "extinction", "albedo", "transport", "surface"});
    TransferRegion r;
    r.name = o.string("name", "");
    r.triangle = o.has("triangle");
    if (r.triangle) {
        if (o.has("value") || o.has("gradient")) o.fail("triangle", "a region is a triangle or a rectangle (value and gradient), not both");
        const nlohmann::json& t = o.raw("triangle");
        const auto corner = [](const nlohmann::json& c) {
            return c.is_array() && c.size() == 2 && c[0].is_number() && c[1].is_number() && std::isfinite(c[0].get<double>()) &&
                   std::isfinite(c[1].get<double>());
        };
        if (!t.is_array() || t.size() != 3 || !corner(t[0]) || !corner(t[1]) || !corner(t[2]))
            o.fail("triangle", "expected three [value, gradient] corners");
        for (int i = 0; i < 3; ++i) r.corners[size_t(i)] = glm::vec2(t[size_t(i)][0].get<float>(), t[size_t(i)][1].get<float>());
        const glm::vec2 u = r.corners[1] - r.corners[0], v = r.corners[2] - r.corners[0];
        if (!(std::abs(u.x * v.y - u.y * v.x) > 0.0f)) o.fail("triangle", "its corners lie on one line");
        for (const glm::vec2& c : r.corners)
            if (c.y < 0.0f) o.fail("triangle", "a gradient magnitude is 0 or more");
    } else {
        const auto range = [&](const std::string& key) {
            const std::vector<float> v = o.numbers(key, 2);
            if (!(v[0] < v[1]) || !std::isfinite(v[0]) || !std::isfinite(v[1])) o.fail(key, "expected [lo, hi], finite, with lo < hi");
            return glm::vec2(v[0], v[1]);
        };
        if (!o.has("value")) o.fail("a region needs \"value\" and \"gradient\" ranges (a rectangle) or \"triangle\" corners");
        r.value = range("value");
        if (o.has("gradient")) r.gradient = range("gradient");
        if (r.gradient.x < 0.0f) o.fail("gradient", "a gradient magnitude is 0 or more");
    }
    r.fade = o.number("fade", 0.0f);
    if (!(r.fade >= 0.0f && r.fade <= 1.0f)) o.fail("fade", "must lie in [0, 1]");
    r.extinction = o.number("extinction");
    if (!(r.extinction >= 0.0f) || !std::isfinite(r.extinction)) o.fail("extinction", "must be a finite 0 or more");
    r.albedo = o.vec3("albedo", glm::vec3(1.0f));
    if (glm::any(glm::lessThan(r.albedo, glm::vec3(0))) || glm::any(glm::greaterThan(r.albedo, glm::vec3(1))))
        o.fail("albedo", "each component must lie in [0, 1]");
    if (o.has("transport")) {
        r.transport = o.vec3("transport");
        if (!(glm::all(glm::greaterThan(*r.transport, glm::vec3(0))) && glm::all(glm::lessThanEqual(*r.transport, glm::vec3(1)))))
            o.fail("transport", "each component must lie in (0, 1]");
    }
    if (o.has("surface")) {
        r.surface = o.number("surface");
        if (!(*r.surface >= 0.0f && *r.surface <= 1.0f)) o.fail("surface", "must lie in [0, 1]");
    }
    return r;
}

Material readMaterial(const JsonObject& o) {
    o.rejectUnknown({"density_scale", "density_units", "albedo", "anisotropy", "transfer_function", "transfer_function_2d"});
    Material m;
    m.density_scale = o.number("density_scale", m.density_scale);
    if (m.density_scale < 0) o.fail("density_scale", "must be 0 or more");
    m.density_units = o.choice("density_units", {"world", "voxel"}, "world") == "voxel" ? DensityUnits::Voxel : DensityUnits::World;
    m.albedo = o.vec3("albedo", m.albedo);
    if (glm::any(glm::lessThan(m.albedo, glm::vec3(0))) || glm::any(glm::greaterThan(m.albedo, glm::vec3(1))))
        o.fail("albedo", "each component must lie in [0, 1]");
    m.anisotropy = o.number("anisotropy", m.anisotropy);
    if (!(m.anisotropy > -1 && m.anisotropy < 1)) o.fail("anisotropy", "must lie in (-1, 1)");
    if (o.has("transfer_function")) {
        for (const auto& p : o.objects("transfer_function")) {
            p.rejectUnknown({"value", "extinction", "albedo"});
            TransferPoint t{p.number("value"), p.number("extinction"), p.vec3("albedo", glm::vec3(1))};
            if (t.extinction < 0) p.fail("extinction", "must be 0 or more");
            if (!m.transfer.empty() && t.value <= m.transfer.back().value)
                p.fail("value", "control points must have increasing values");
            m.transfer.push_back(t);
        }
        if (m.transfer.size() < 2) o.fail("transfer_function", "needs at least 2 control points");
    }
    if (o.has("transfer_function_2d")) {
        if (o.has("transfer_function")) o.fail("transfer_function_2d", "a material has one transfer function: remove transfer_function");
        if (o.raw("transfer_function_2d").is_string()) {   // a preset's name
            const std::string name = o.string("transfer_function_2d");
            const TransferPreset* preset = findTransferPreset(name);
            if (!preset) {
                std::string names;
                for (const TransferPreset& p : transferPresets()) names += (names.empty() ? "" : ", ") + p.name;
                o.fail("transfer_function_2d", "'" + name + "' is not a preset (" + names + ") or a list of regions");
            }
            m.transfer_2d = preset->regions;
        } else {
            for (const auto& r : o.objects("transfer_function_2d")) m.transfer_2d.push_back(readTransferRegion(r));
        }
        if (m.transfer_2d.empty()) o.fail("transfer_function_2d", "needs at least one region");
        // A per-region property the regions share: on every region, or on none.
        auto everyOrNone = [&](const char* what, auto has) {
            for (size_t i = 0; i < m.transfer_2d.size(); ++i)
                if (has(m.transfer_2d[i]) != has(m.transfer_2d[0])) {
                    const size_t at = has(m.transfer_2d[i]) ? 0 : i;   // the first region without it
                    const std::string& name = m.transfer_2d[at].name;
                    o.fail("transfer_function_2d", std::string("give every region ") + what + " or none: " +
                                                       (name.empty() ? "the region at index " + std::to_string(at) : "'" + name + "'") + " has none");
                }
        };
        everyOrNone("a transport colour", [](const TransferRegion& r) { return r.transport.has_value(); });
        everyOrNone("a surface weight", [](const TransferRegion& r) { return r.surface.has_value(); });
    }
    return m;
}

// World coordinates voxlux accepts: beyond them a float has less than a unit of precision left
// for a ray's steps, and index coordinates would leave int's range.
constexpr float kMaxWorldCoordinate = 1e9f;

glm::vec3 readPoint(const JsonObject& o, const std::string& key) {
    const glm::vec3 p = o.vec3(key);
    if (glm::compMax(glm::abs(p)) > kMaxWorldCoordinate) o.fail(key, "each coordinate must lie within +-1e9");
    return p;
}

// A unit vector: kept as written when it is one, so a scene that voxlux wrote reads back to the
// same floats. A vector whose length overflows or underflows a float is scaled by its largest
// component before normalising.
glm::vec3 readDirection(const JsonObject& o, const std::string& key) {
    const glm::vec3 d = o.vec3(key);
    const float largest = glm::compMax(glm::abs(d));
    if (largest == 0) o.fail(key, "must not be zero");
    const float length = glm::length(d);
    if (std::abs(length - 1.0f) <= 1e-6f) return d;
    return std::isfinite(length) && length > 1e-18f ? glm::normalize(d) : glm::normalize(d / largest);
}

// The camera's transform: a matrix, or position, look_at and up.
Camera readCameraPose(const JsonObject& o) {
    Camera c;
    if (o.has("matrix")) {
        auto m = o.numbers("matrix", 16);
        glm::mat4 mat;
        for (int i = 0; i < 16; ++i) mat[i / 4][i % 4] = m[i];  // column-major, as glm and GLSL
        if (glm::compMax(glm::abs(glm::vec3(mat[3]))) > kMaxWorldCoordinate)
            o.fail("matrix", "the position (elements 12-14) must lie within +-1e9");
        // Rays need three independent axes; a determinant near 0 (a matrix of zeros) has none.
        const glm::mat3 axes(mat);
        const float scale = glm::compMax(glm::abs(glm::vec3(glm::length(axes[0]), glm::length(axes[1]), glm::length(axes[2]))));
        if (!(scale > 0) || !(std::abs(glm::determinant(axes / scale)) > 1e-6f))
            o.fail("matrix", "its rotation part (elements 0-10) must be invertible");
        c.matrix = mat;
        return c;
    }
    c.position = readPoint(o, "position");
    c.look_at = readPoint(o, "look_at");
    // Kept as written (the camera normalises it), so an edit of `up` is an edit of the scene.
    c.up = o.vec3("up", c.up);
    if (glm::compMax(glm::abs(c.up)) > kMaxWorldCoordinate) o.fail("up", "each component must lie within +-1e9");
    if (glm::length(c.look_at - c.position) == 0) o.fail("look_at", "must differ from position");
    if (glm::length(glm::cross(c.look_at - c.position, c.up)) < 1e-6f)
        o.fail("up", "must not be parallel to the view direction");
    return c;
}

// A pose's translate, rotate and scale (a number or one per axis), each defaulting to `fallback`'s.
TransformKey readPose(const JsonObject& o, const TransformKey& fallback) {
    TransformKey k = fallback;
    if (o.has("translate")) k.translate = readPoint(o, "translate");
    k.rotate = o.vec3("rotate", k.rotate);
    if (!std::isfinite(k.rotate.x + k.rotate.y + k.rotate.z)) o.fail("rotate", "must be finite degrees");
    if (o.has("scale")) k.scale = o.raw("scale").is_number() ? glm::vec3(o.number("scale")) : o.vec3("scale");
    if (!(glm::compMin(k.scale) > 0) || !std::isfinite(glm::compMax(k.scale)))
        o.fail("scale", "must be finite and > 0 (a number, or one per axis)");
    return k;
}

// The keys of an animated transform, the array at `o`'s `key`: {"frame": f, translate, rotate,
// scale}, frames increasing.
std::vector<TransformKey> readTransformKeys(const JsonObject& o, const std::string& key) {
    if (!o.raw(key).is_array() || o.raw(key).empty())
        o.fail(key, "expected a list of {\"frame\": f, \"translate\": ..., \"rotate\": ..., \"scale\": ...}");
    std::vector<TransformKey> keys;
    for (size_t i = 0; i < o.raw(key).size(); ++i) {
        const JsonObject entry = o.element(key, i);
        entry.rejectUnknown({"frame", "translate", "rotate", "scale"});
        if (!entry.has("frame")) entry.fail("frame", "is required in every key");
        TransformKey k = readPose(entry, TransformKey{});
        k.frame = entry.number("frame");
        if (!std::isfinite(k.frame) || std::abs(k.frame) > 1e9) entry.fail("frame", "must be a finite frame number");
        if (!keys.empty() && !(k.frame > keys.back().frame)) entry.fail("frame", "must follow the previous key's frame");
        keys.push_back(k);
    }
    return keys;
}

// A transform object: a matrix; or translate, rotate and scale, still, keyed per frame (`keys`)
// or from a Nuke .chan file (`chan`, which gives translate and rotate; `scale` applies to every
// key).
VolumeTransform readTransformObject(const JsonObject& o, const std::string& base_dir) {
    VolumeTransform t;
    o.rejectUnknown({"translate", "rotate", "scale", "rotate_order", "matrix", "keys", "chan"});
    if (o.has("matrix")) {
        for (const char* key : {"translate", "rotate", "scale", "rotate_order", "keys", "chan"})
            if (o.has(key)) o.fail(key, "goes with translate, rotate and scale, not with a matrix");
        t.matrix = readCameraPose(o).matrix;   // the same checks as a camera's: finite, invertible
        return t;
    }
    const std::string order = o.choice("rotate_order", {std::begin(kRotateOrderNames), std::end(kRotateOrderNames)}, "xyz");
    t.rotate_order = RotateOrder(std::find(std::begin(kRotateOrderNames), std::end(kRotateOrderNames), order) - std::begin(kRotateOrderNames));
    const TransformKey still = readPose(o, TransformKey{});
    t.translate = still.translate, t.rotate = still.rotate, t.scale = still.scale;
    if (o.has("keys") && o.has("chan")) o.fail("chan", "goes with scale and rotate_order, not with keys");
    if (o.has("chan")) {
        for (const char* key : {"translate", "rotate"})
            if (o.has(key)) o.fail(key, "comes from the .chan file, which gives translate and rotate per frame");
        t.chan = resolvePath(o.string("chan"), base_dir);
        t.keys = readChanFile(t.chan).keys;
        for (TransformKey& k : t.keys) k.scale = t.scale;
    } else if (o.has("keys")) {
        for (const char* key : {"translate", "rotate", "scale"})
            if (o.has(key)) o.fail(key, "goes in each key of keys, not beside them");
        t.keys = readTransformKeys(o, "keys");
    }
    return t;
}

// volume.transform: a transform object, or an array of its keys.
VolumeTransform readVolumeTransform(const JsonObject& volume, const std::string& base_dir) {
    if (volume.raw("transform").is_array()) {
        VolumeTransform t;
        t.keys = readTransformKeys(volume, "transform");
        return t;
    }
    return readTransformObject(volume.object("transform"), base_dir);
}

// An instance: a still pose (translate, rotate and scale, or a matrix).
VolumeTransform readInstance(const JsonObject& o, const std::string& base_dir) {
    for (const char* key : {"keys", "chan"})
        if (o.has(key)) o.fail(key, "an instance is still: translate, rotate and scale, or a matrix");
    return readTransformObject(o, base_dir);
}

// The keys of `volume` and of an entry of `volumes` (which also holds its material and emission).
const std::vector<std::string> kVolumeKeys{"name", "path", "frames", "density", "color", "level_set", "up", "transform", "instances", "role", "enabled"};

// The cache, its frames and its placement; not its name, material or emission (readVolumes).
VolumeSpec readVolume(const JsonObject& o, const std::string& base_dir) {
    VolumeSpec v;
    v.path = o.string("path");
    v.path = resolvePath(v.path, base_dir);
    if (o.has("frames") && o.raw("frames").is_string()) {
        try {
            v.frames = FrameSet::parse(o.string("frames"));
        } catch (const std::invalid_argument& e) {
            o.fail("frames", e.what());
        }
    } else if (o.has("frames")) {
        // Read as doubles, exact for every int (floats are not past 2^24); checked before converting.
        const nlohmann::json& range = o.raw("frames");
        const auto frameNumber = [](const nlohmann::json& x) {
            return x.is_number() && x.get<double>() >= -2147483648.0 && x.get<double>() < 2147483648.0 && x.get<double>() == std::floor(x.get<double>());
        };
        if (!range.is_array() || range.size() != 2 || !frameNumber(range[0]) || !frameNumber(range[1]) ||
            range[0].get<double>() > range[1].get<double>())
            o.fail("frames", "expected [first, last] integers with first <= last, or a string such as \"1-240x2,300\"");
        v.frames = FrameSet(int(range[0].get<double>()), int(range[1].get<double>()));
    }
    if (o.has("density")) v.density = readGridRef(o, "density");
    if (o.has("color")) v.color = readGridRef(o, "color");
    v.level_set = o.choice("level_set", {"reject", "fog"}, "reject") == "fog"
                      ? LevelSetPolicy::ConvertToFog
                      : LevelSetPolicy::Reject;
    const std::string up = o.choice("up", {"auto", "x", "y", "z"}, "auto");
    v.up = up == "x" ? UpAxis::X : up == "y" ? UpAxis::Y : up == "z" ? UpAxis::Z : UpAxis::Auto;
    if (o.has("transform")) v.transform = readVolumeTransform(o, base_dir);
    if (v.transform && !v.transform->keys.empty() && !hasFramePattern(v.path))
        o.fail("transform", "is keyed per frame, but path names one file, not a #### sequence");
    const std::string role = o.choice("role", kVolumeRoleNames, "visible");
    v.role = VolumeRole(std::find(kVolumeRoleNames.begin(), kVolumeRoleNames.end(), role) - kVolumeRoleNames.begin());
    v.enabled = o.boolean("enabled", true);
    if (o.has("instances")) {
        if (!o.raw("instances").is_array() || o.raw("instances").empty())
            o.fail("instances", "expected a list of transforms ({\"translate\", \"rotate\", \"scale\"} or {\"matrix\"})");
        for (size_t i = 0; i < o.raw("instances").size(); ++i) v.instances.push_back(readInstance(o.element("instances", i), base_dir));
    }
    return v;
}


// The camera's lens: fov, or focal_length with film_back (mm); a file's lens replaces both.
void readLens(const JsonObject& o, Camera& c) {
    if (o.has("fov") && o.has("focal_length")) o.fail("focal_length", "gives the field of view, which fov gives too: set one of them");
    const bool lens_in_file = c.file && !c.file->vertical_fov.empty();
    for (const char* key : {"fov", "focal_length", "film_back"})
        if (lens_in_file && o.has(key)) o.fail(key, "comes from the camera file, which has a lens");
    c.fov = o.number("fov", c.fov);
    if (!(c.fov > 0 && c.fov < 180)) o.fail("fov", "must lie in (0, 180) degrees");
    c.focal_length = o.number("focal_length", c.focal_length);
    if (o.has("focal_length") && !(c.focal_length > 0 && c.focal_length < 1e6f)) o.fail("focal_length", "must lie in (0, 1e6) mm");
    if (o.has("film_back")) {
        const std::vector<float> back = o.numbers("film_back", 2);
        if (!(back[0] > 0 && back[1] > 0 && back[0] < 1e6f && back[1] < 1e6f)) o.fail("film_back", "must be [width, height] in mm, each in (0, 1e6)");
        if (!o.has("focal_length")) o.fail("film_back", "goes with focal_length");
        c.film_back = glm::vec2(back[0], back[1]);
    }
}

// Depth of field: fstop, and where the lens is sharp (focus_distance, by default the look_at's
// distance), the scene's unit in millimetres and the rays a pixel takes over the lens.
void readDepthOfField(const JsonObject& o, Camera& c) {
    if (!o.has("fstop")) {
        for (const char* key : {"focus_distance", "world_unit_mm", "lens_samples"})
            if (o.has(key)) o.fail(key, "goes with fstop (depth of field)");
        return;
    }
    c.fstop = o.number("fstop");
    if (!(c.fstop > 0.0f && c.fstop < 1e6f)) o.fail("fstop", "must lie in (0, 1e6): the f-number, focal length over the aperture");
    const bool aimed = !c.file && !c.matrix;
    if (!o.has("focus_distance") && !aimed) o.fail("focus_distance", "is required with fstop when the camera has no look_at");
    c.focus_distance = o.number("focus_distance", glm::distance(c.position, c.look_at));
    if (!(c.focus_distance > 0.0f && c.focus_distance < 1e9f)) o.fail("focus_distance", "must lie in (0, 1e9) world units");
    c.world_unit_mm = o.number("world_unit_mm", c.world_unit_mm);
    if (!(c.world_unit_mm > 0.0f && c.world_unit_mm < 1e9f)) o.fail("world_unit_mm", "must lie in (0, 1e9): millimetres in one world unit");
    c.lens_samples = o.integer("lens_samples", c.lens_samples);
    if (c.lens_samples < 1 || c.lens_samples > 1024) o.fail("lens_samples", "must lie in 1..1024");
}

// camera.file: the pose (and lens) from a Nuke .chan, or a glTF or FBX scene's camera.
CameraFile readCameraFileKeys(const JsonObject& o, const std::string& base_dir) {
    for (const char* key : {"position", "look_at", "up", "matrix", "motion"})
        if (o.has(key)) o.fail(key, "comes from the camera file (camera.file)");
    const std::string path = resolvePath(o.string("file"), base_dir);
    const bool chan = isChanFile(path);
    if (chan && o.has("name")) o.fail("name", "picks a camera of a glTF or FBX file; a .chan holds one");
    if (!chan && o.has("rotate_order")) o.fail("rotate_order", "turns a .chan's rotations; a glTF or FBX camera has its matrix");
    const std::string order = o.choice("rotate_order", {std::begin(kRotateOrderNames), std::end(kRotateOrderNames)}, "zxy");
    return readCameraFile(path, o.string("name", ""), RotateOrder(std::find(std::begin(kRotateOrderNames), std::end(kRotateOrderNames), order) -
                                                                  std::begin(kRotateOrderNames)));
}

Camera readCamera(const JsonObject& o, const std::string& base_dir) {
    o.rejectUnknown({"position", "look_at", "up", "matrix", "fov", "focal_length", "film_back", "motion", "file", "name", "rotate_order",
                     "fstop", "focus_distance", "world_unit_mm", "lens_samples"});
    if (o.has("file")) {
        Camera c;
        c.file = readCameraFileKeys(o, base_dir);
        readLens(o, c);
        readDepthOfField(o, c);
        return c;
    }
    for (const char* key : {"name", "rotate_order"})
        if (o.has(key)) o.fail(key, "goes with camera.file");
    Camera c = readCameraPose(o);
    readLens(o, c);
    readDepthOfField(o, c);
    if (o.has("motion")) {
        const JsonObject m = o.object("motion");
        m.rejectUnknown({"open", "close"});
        const auto pose = [&](const std::string& key) {
            const JsonObject p = m.object(key);
            p.rejectUnknown({"position", "look_at", "up", "matrix"});
            return cameraToWorld(readCameraPose(p));
        };
        c.motion = std::array<glm::mat4, 2>{pose("open"), pose("close")};
    }
    return c;
}

ReferenceSettings readReference(const JsonObject& o) {
    o.rejectUnknown({"spp", "max_bounces", "seed", "roulette_depth"});
    ReferenceSettings r;
    r.spp = o.integer("spp", r.spp);
    if (r.spp < 1 || r.spp > 1000000) o.fail("spp", "must lie in 1..1000000");
    r.max_bounces = o.integer("max_bounces", r.max_bounces);
    if (r.max_bounces < 1 || r.max_bounces > 1000) o.fail("max_bounces", "must lie in 1..1000");
    r.seed = o.integer("seed", r.seed);
    r.roulette_depth = o.integer("roulette_depth", r.roulette_depth);
    if (r.roulette_depth < 1) o.fail("roulette_depth", "must be at least 1");
    return r;
}

MotionBlur readMotionBlur(const JsonObject& o) {
    o.rejectUnknown({"shutter", "velocity", "velocity_scale", "fps", "samples"});
    MotionBlur m;
    if (o.has("shutter")) {
        const auto shutter = o.numbers("shutter", 2);
        if (!(shutter[0] >= -1 && shutter[0] <= shutter[1] && shutter[1] <= 1))
            o.fail("shutter", "expected [open, close] in frames, -1 <= open <= close <= 1");
        m.shutter_open = shutter[0];
        m.shutter_close = shutter[1];
    }
    if (o.has("velocity")) m.velocity = readGridRef(o, "velocity");
    m.velocity_scale = o.number("velocity_scale", m.velocity_scale);
    if (!(std::abs(m.velocity_scale) <= 1e6f)) o.fail("velocity_scale", "must lie in [-1e6, 1e6]");
    m.fps = o.number("fps", m.fps);
    if (!(m.fps >= 1e-3f && m.fps <= 1e4f)) o.fail("fps", "must lie in [0.001, 10000] frames per second");
    m.samples = o.integer("samples", m.samples);
    if (m.samples < 1 || m.samples > 64) o.fail("samples", "must lie in 1..64");
    return m;
}

RenderSettings readRender(const JsonObject& o) {
    o.rejectUnknown({"resolution", "step", "shadow_step", "transmittance_cutoff", "exposure", "filter", "backend", "method", "reference",
                     "motion_blur", "region"});
    RenderSettings r;
    if (o.has("resolution")) {
        auto res = o.numbers("resolution", 2);
        // Checked before converting: a float outside int's range has no int value.
        const auto pixels = [](float x) { return x >= 1 && x <= 16384 && x == std::floor(x); };
        if (!pixels(res[0]) || !pixels(res[1])) o.fail("resolution", "expected [width, height], integers in 1..16384");
        r.width = int(res[0]);
        r.height = int(res[1]);
    }
    r.step = o.number("step", r.step);
    if (!(r.step >= 0.01f && r.step <= 64)) o.fail("step", "must lie in [0.01, 64] voxels");
    r.shadow_step = o.number("shadow_step", r.shadow_step);
    if (!(r.shadow_step >= 0.01f && r.shadow_step <= 64)) o.fail("shadow_step", "must lie in [0.01, 64] voxels");
    r.transmittance_cutoff = o.number("transmittance_cutoff", r.transmittance_cutoff);
    if (!(r.transmittance_cutoff > 0 && r.transmittance_cutoff < 1))
        o.fail("transmittance_cutoff", "must lie in (0, 1)");
    r.exposure = o.number("exposure", r.exposure);
    if (!(std::abs(r.exposure) <= 64)) o.fail("exposure", "must lie in [-64, 64] stops");
    r.filter = o.choice("filter", {"trilinear", "tricubic"}, "trilinear") == "tricubic" ? Filter::Tricubic : Filter::Trilinear;
    std::string b = o.choice("backend", {"auto", "cpu", "gl"}, "auto");
    r.backend = b == "cpu" ? Backend::Cpu : b == "gl" ? Backend::Gl : Backend::Auto;
    r.method = o.choice("method", {"march", "reference"}, "march") == "reference" ? RenderMethod::Reference : RenderMethod::March;
    // The reference renderer exists only on the CPU; auto picks the CPU for it.
    if (r.method == RenderMethod::Reference && r.backend == Backend::Gl)
        o.fail("method", "reference runs on the cpu backend only (render.backend is \"gl\")");
    if (o.has("reference")) r.reference = readReference(o.object("reference"));
    if (o.has("motion_blur")) r.motion_blur = readOptional(o, "motion_blur", readMotionBlur);
    if (o.has("region") && o.raw("region") != false) {   // false: the whole image
        const auto b = o.numbers("region", 4);
        r.region = std::array<float, 4>{b[0], b[1], b[2], b[3]};
        if (!isRegion(*r.region)) o.fail("region", kRegionExpected);
    }
    return r;
}


SurfaceShading readSurface(const JsonObject& o) {
    o.rejectUnknown({"gradient_low", "gradient_high", "specular", "shininess"});
    SurfaceShading sf;
    sf.gradient_low = o.number("gradient_low", sf.gradient_low);
    sf.gradient_high = o.number("gradient_high", sf.gradient_high);
    if (!(sf.gradient_low >= 0 && sf.gradient_high > sf.gradient_low && std::isfinite(sf.gradient_high)))
        o.fail("gradient_high", "needs 0 <= gradient_low < gradient_high");
    sf.specular = o.number("specular", sf.specular);
    if (!(sf.specular >= 0 && std::isfinite(sf.specular))) o.fail("specular", "must be a finite value >= 0");
    sf.shininess = o.number("shininess", sf.shininess);
    if (!(sf.shininess >= 1 && sf.shininess <= 10000)) o.fail("shininess", "must lie in [1, 10000]");
    return sf;
}

Perturbation readPerturbation(const JsonObject& o) {
    o.rejectUnknown({"seed", "scale", "octaves", "lacunarity", "gain", "density", "transport", "displacement",
                     "velocity", "time"});
    Perturbation p;
    p.seed = o.integer("seed", p.seed);
    p.scale = o.number("scale", p.scale);
    if (!(p.scale >= 0) || !std::isfinite(p.scale)) o.fail("scale", "must be a finite size >= 0 (0 = automatic)");
    p.octaves = o.integer("octaves", p.octaves);
    if (p.octaves < 1 || p.octaves > 8) o.fail("octaves", "must lie in 1..8");
    p.lacunarity = o.number("lacunarity", p.lacunarity);
    if (!(p.lacunarity >= 1 && p.lacunarity <= 8)) o.fail("lacunarity", "must lie in [1, 8]");
    p.gain = o.number("gain", p.gain);
    if (!(p.gain > 0 && p.gain <= 1)) o.fail("gain", "must lie in (0, 1]");
    p.density = o.number("density", p.density);
    if (!(p.density >= 0 && p.density <= 10)) o.fail("density", "must lie in [0, 10]");
    p.transport = o.number("transport", p.transport);
    if (!(p.transport >= 0 && p.transport <= 1)) o.fail("transport", "must lie in [0, 1]");
    p.displacement = o.number("displacement", p.displacement);
    if (!(p.displacement >= 0 && p.displacement <= 64)) o.fail("displacement", "must lie in [0, 64] voxels");
    p.velocity = o.vec3("velocity", p.velocity);
    if (!std::isfinite(p.velocity.x + p.velocity.y + p.velocity.z)) o.fail("velocity", "must be finite");
    p.time = o.number("time", p.time);
    if (!std::isfinite(p.time)) o.fail("time", "must be finite");
    return p;
}

Effects readEffects(const JsonObject& o) {
    std::vector<std::string> keys = {"shadows", "surface", "perturbation", "light_resolution", "light_memory_mb"};
    for (const std::string& key : methodSettingKeys()) keys.push_back(key);
    o.rejectUnknown(keys);
    Effects e;
    const std::string shadows = o.choice("shadows", kShadowMethodNames, shadowMethodName(ShadowMethod::Raymarch));
    e.shadows = ShadowMethod(std::find(kShadowMethodNames.begin(), kShadowMethodNames.end(), shadows) - kShadowMethodNames.begin());
    readMethodSettings(o, e);
    if (o.has("surface")) e.surface = readOptional(o, "surface", readSurface);
    if (o.has("perturbation")) e.perturbation = readOptional(o, "perturbation", readPerturbation);
    e.light_resolution = o.integer("light_resolution", e.light_resolution);
    if (e.light_resolution < 2 || e.light_resolution > 1024) o.fail("light_resolution", "must lie in 2..1024 cells");
    e.light_memory_mb = o.integer("light_memory_mb", e.light_memory_mb);
    if (e.light_memory_mb < 1) o.fail("light_memory_mb", "must be at least 1");
    return e;
}

PixelType readPixelType(const JsonObject& o) {
    return o.choice("pixel_type", {"half", "float"}, "half") == "float" ? PixelType::Float : PixelType::Half;
}

// An AOV is a name, or {"name": ..., "pixel_type": ...} to give its layer its own pixel type.
AovSpec readAov(const JsonObject& output, size_t index) {
    auto known = [](const std::string& name) {
        return std::find(knownAovs().begin(), knownAovs().end(), name) != knownAovs().end();
    };
    const std::string expected = " (expected direct, ambient, indirect, emission, transmittance, depth, variance, coverage or light_groups)";
    const auto& a = output.raw("aovs")[index];
    if (!a.is_object()) {
        const std::string name = a.is_string() ? a.get<std::string>() : jsonText(a);
        if (!known(name)) output.fail("aovs", "unknown AOV '" + name + "'" + expected);
        return {name, std::nullopt};
    }
    JsonObject o = output.element("aovs", index);
    o.rejectUnknown({"name", "pixel_type"});
    AovSpec aov{o.string("name"), std::nullopt};
    if (!known(aov.name)) o.fail("name", "unknown AOV '" + aov.name + "'" + expected);
    if (o.has("pixel_type")) aov.pixel_type = readPixelType(o);
    return aov;
}

OutputSpec readOutput(const JsonObject& o) {
    o.rejectUnknown({"path", "pixel_type", "compression", "aovs", "preview", "deep", "deep_samples"});
    OutputSpec out;
    out.path = o.string("path", "");
    out.preview = o.string("preview", "");
    // The extension never lies: the image is OpenEXR, the preview PNG.
    const auto endsWith = [](std::string name, const std::string& ext) {
        std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        return name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0;
    };
    if (!out.path.empty() && !endsWith(out.path, ".exr"))
        o.fail("path", "'" + out.path + "' does not end in .exr: the image is written as OpenEXR (an sRGB PNG is the "
                       "preview: output.preview, or --preview FILE.png)");
    if (!out.preview.empty() && !endsWith(out.preview, ".png"))
        o.fail("preview", "'" + out.preview + "' does not end in .png: the preview is written as PNG");
    out.pixel_type = readPixelType(o);
    out.compression = o.choice("compression", knownCompressions(), "zip");
    out.deep = o.boolean("deep", out.deep);
    out.deep_samples = o.integer("deep_samples", out.deep_samples);
    if (out.deep_samples < 1 || out.deep_samples > 64) o.fail("deep_samples", "must lie in 1..64");
    if (o.has("aovs")) {
        const auto& list = o.raw("aovs");
        if (!list.is_array()) o.fail("aovs", "expected an array of AOV names or objects");
        for (size_t i = 0; i < list.size(); ++i) {
            AovSpec aov = readAov(o, i);
            for (size_t j = 0; j < out.aovs.size(); ++j)
                if (out.aovs[j].name == aov.name)
                    o.fail("aovs/" + std::to_string(i),
                           "duplicate AOV '" + aov.name + "' (first at " + o.pointer("aovs/" + std::to_string(j)) + ")");
            out.aovs.push_back(aov);
        }
    }
    return out;
}

// Emitted colours: unbounded, but finite and >= 0.
glm::vec3 readEmittedColor(const JsonObject& o, const std::string& key) {
    const glm::vec3 c = o.vec3(key);
    if (!(glm::all(glm::greaterThanEqual(c, glm::vec3(0.0f))) && std::isfinite(c.x + c.y + c.z)))
        o.fail(key, "must be finite and >= 0");
    return c;
}

// Each kind takes its own keys; another kind's are refused, as they would be ignored.
EmissionSource readEmissionSource(const JsonObject& o) {
    EmissionSource e;
    const std::string kind = o.choice("kind", {"constant", "blackbody", "ramp"}, "constant");
    e.kind = kind == "blackbody" ? EmissionKind::Blackbody : kind == "ramp" ? EmissionKind::Ramp : EmissionKind::Constant;
    std::vector<std::string> keys{"grid", "kind", "intensity"};
    if (e.kind == EmissionKind::Constant) keys.push_back("color");
    if (e.kind == EmissionKind::Ramp) keys.push_back("ramp");
    if (e.kind == EmissionKind::Blackbody) {
        keys.insert(keys.end(), {"temperature_scale", "temperature_offset", "cutoff", "normalization"});
        if (o.choice("normalization", {"luminance", "physical"}, "luminance") == "physical") {
            e.normalization = BlackbodyNormalization::Physical;
            keys.push_back("reference_temperature");
        }
    }
    o.rejectUnknown(keys);
    e.grid = readGridRef(o, "grid");
    e.intensity = o.number("intensity", e.intensity);
    if (!(e.intensity >= 0) || !std::isfinite(e.intensity)) o.fail("intensity", "must be a finite number >= 0");
    if (o.has("color")) e.color = readEmittedColor(o, "color");
    if (e.kind == EmissionKind::Ramp) {
        for (const auto& p : o.objects("ramp")) {
            p.rejectUnknown({"value", "color"});
            RampPoint r{p.number("value"), readEmittedColor(p, "color")};
            if (!std::isfinite(r.value)) p.fail("value", "must be finite");
            if (!e.ramp.empty() && r.value <= e.ramp.back().value) p.fail("value", "ramp points must have increasing values");
            e.ramp.push_back(r);
        }
        if (e.ramp.size() < 2) o.fail("ramp", "needs at least 2 points");
    }
    if (e.kind == EmissionKind::Blackbody) {
        e.temperature_scale = o.number("temperature_scale", e.temperature_scale);
        if (!(e.temperature_scale > 0) || !std::isfinite(e.temperature_scale))
            o.fail("temperature_scale", "must be a finite number > 0");
        e.temperature_offset = o.number("temperature_offset", e.temperature_offset);
        if (!std::isfinite(e.temperature_offset)) o.fail("temperature_offset", "must be finite");
        e.cutoff = o.number("cutoff", e.cutoff);
        if (!(e.cutoff >= 0) || !std::isfinite(e.cutoff)) o.fail("cutoff", "must be a finite temperature >= 0 K");
        e.reference_temperature = o.number("reference_temperature", e.reference_temperature);
        if (!(e.reference_temperature > 0) || !std::isfinite(e.reference_temperature))
            o.fail("reference_temperature", "must be a finite temperature > 0 K");
    }
    // Value 0 is empty space (the grids' background): emitting there would light whole bricks
    // and stop at their edges.
    if (emissionRadiance(e, 0.0f, kXyzD65ToAcescg) != glm::vec3(0.0f)) {
        if (e.kind == EmissionKind::Ramp) o.fail("ramp", "must be black at value 0 (empty space emits nothing)");
        char kelvin[32];
        std::snprintf(kelvin, sizeof kelvin, "%g", double(e.temperature_offset));
        o.fail("temperature_offset", "value 0 (empty space) would emit at " + std::string(kelvin) +
                                         " K: keep the offset below cutoff");
    }
    return e;
}

// One grading step: exactly one of look, cdl, cdl_file or lut, with the keys that kind takes.
GradeStep readGradeStep(const JsonObject& o, const std::string& base_dir) {
    const std::vector<std::string> kinds{"look", "cdl", "cdl_file", "lut"};
    std::vector<std::string> present;
    for (const auto& k : kinds)
        if (o.has(k)) present.push_back(k);
    if (present.size() != 1) o.fail("expected exactly one of look, cdl, cdl_file or lut");
    GradeStep g;
    const std::string& kind = present[0];
    if (kind == "look") {
        o.rejectUnknown({"look", "inverse"});
        g.kind = GradeKind::Look;
        g.look = o.string("look");
    } else if (kind == "cdl") {
        o.rejectUnknown({"cdl", "space", "inverse", "clamp"});
        g.kind = GradeKind::Cdl;
        JsonObject c = o.object("cdl");
        c.rejectUnknown({"slope", "offset", "power", "saturation"});
        g.slope = c.vec3("slope", g.slope);
        g.offset = c.vec3("offset", g.offset);
        g.power = c.vec3("power", g.power);
        g.saturation = c.number("saturation", g.saturation);
        if (glm::any(glm::lessThan(g.slope, glm::vec3(0.0f)))) c.fail("slope", "must be 0 or more");
        if (glm::any(glm::lessThanEqual(g.power, glm::vec3(0.0f)))) c.fail("power", "must be more than 0");
        if (!(g.saturation >= 0.0f)) c.fail("saturation", "must be 0 or more");
    } else if (kind == "cdl_file") {
        o.rejectUnknown({"cdl_file", "cccid", "space", "inverse", "clamp"});
        g.kind = GradeKind::CdlFile;
        g.file = resolvePath(o.string("cdl_file"), base_dir);
        g.cccid = o.string("cccid", "");
    } else {
        o.rejectUnknown({"lut", "interpolation", "space", "inverse"});
        g.kind = GradeKind::Lut;
        g.file = resolvePath(o.string("lut"), base_dir);
        g.interpolation = o.choice("interpolation", {"nearest", "linear", "tetrahedral", "best"}, "best");
    }
    g.space = o.string("space", "");
    g.inverse = o.boolean("inverse", false);
    g.clamp = o.boolean("clamp", false);
    return g;
}

ColorSettings readColor(const JsonObject& o, const std::string& base_dir) {
    o.rejectUnknown({"config", "working_space", "output_space", "grade", "unpremultiply", "display", "view"});
    ColorSettings c;
    if (o.has("config")) c.config = resolvePath(o.string("config"), base_dir);
    c.working_space = o.string("working_space", "");
    c.output_space = o.string("output_space", "");
    if (o.has("grade"))
        for (const auto& step : o.objects("grade")) c.grade.push_back(readGradeStep(step, base_dir));
    c.unpremultiply = o.boolean("unpremultiply", c.unpremultiply);
    c.display = o.string("display", "");
    c.view = o.string("view", "");
    return c;
}

// A light's list of volume names (light linking), unset when the key is absent.
std::optional<std::vector<std::string>> readVolumeNames(const JsonObject& o, const std::string& key) {
    if (!o.has(key)) return std::nullopt;
    const nlohmann::json& list = o.raw(key);
    if (!list.is_array() || !std::all_of(list.begin(), list.end(), [](const nlohmann::json& n) { return n.is_string(); }))
        o.fail(key, "must be a list of volume names");
    return list.get<std::vector<std::string>>();
}

// "the scene's volumes are 'smoke', 'fire'", for a message about a name that is none of them.
std::string volumeNamesText(const std::vector<VolumeSpec>& volumes) {
    std::string text;
    for (const VolumeSpec& v : volumes) text += (text.empty() ? "'" : ", '") + v.name + "'";
    return "the scene's volumes are " + text;
}

}  // namespace

namespace {

EnvironmentSettings readEnvironment(const JsonObject& o, const std::string& base_dir) {
    EnvironmentSettings e;
    e.map = resolvePath(o.string("map"), base_dir);
    e.map_colorspace = o.string("map_colorspace", "");
    if (o.has("up")) {
        const nlohmann::json& up = o.raw("up");
        if (up.is_string()) {
            const std::string axis = o.choice("up", {"x", "y", "z"}, "y");
            e.up = glm::vec3(axis == "x", axis == "y", axis == "z");
        } else {
            e.up = readDirection(o, "up");
        }
    }
    e.rotation = o.number("rotation", 0.0f);
    if (!std::isfinite(e.rotation)) o.fail("rotation", "must be a finite number of degrees");
    e.visible_to_camera = o.boolean("visible_to_camera", false);
    e.median_cut_lights = o.integer("median_cut_lights", e.median_cut_lights);
    if (e.median_cut_lights < 0 || e.median_cut_lights > 1024) o.fail("median_cut_lights", "must lie in [0, 1024]");
    e.remainder = o.choice("remainder", kEnvironmentRemainderNames, "floor") == "none" ? EnvironmentRemainder::None
                                                                                      : EnvironmentRemainder::Floor;
    return e;
}

}  // namespace

Light readLight(const JsonObject& o, const std::string& base_dir) {
    Light l;
    std::string type = o.choice("type", {"directional", "point", "spot", "ambient", "environment"}, "directional");
    l.type = type == "point"         ? LightType::Point
             : type == "spot"        ? LightType::Spot
             : type == "ambient"     ? LightType::Ambient
             : type == "environment" ? LightType::Environment
                                     : LightType::Directional;
    if (l.type == LightType::Ambient || l.type == LightType::Environment)
        for (const char* key : {"volumes", "shadow_volumes"})
            if (o.has(key)) o.fail(key, "an " + type + " light lights every volume: link a directional, point or spot light");
    if (l.type == LightType::Ambient)
        o.rejectUnknown({"name", "enabled", "type", "color", "intensity", "group"});
    else if (l.type == LightType::Environment)
        o.rejectUnknown({"name", "enabled", "type", "color", "intensity", "group", "map", "map_colorspace", "up", "rotation",
                         "visible_to_camera", "median_cut_lights", "remainder"});
    else
        o.rejectUnknown({"name", "enabled", "type", "position", "direction", "color", "intensity", "cone_angle",
                         "cone_softness", "group", "volumes", "shadow_volumes"});
    l.name = o.string("name", "");
    l.group = o.string("group", "");
    // The name becomes the EXR layer lightgroup.<group>: Nuke splits channel names at dots.
    const bool layer_name = !l.group.empty() && std::all_of(l.group.begin(), l.group.end(), [](unsigned char c) {
        return std::isalnum(c) || c == '_' || c == '-';
    });
    if (o.has("group") && !layer_name)
        o.fail("group", "'" + l.group + "' is not a layer name: use letters, digits, '_' and '-'");
    if (l.group == kEmissionLayer) o.fail("group", "'emission' is the emitted light's own group (lightgroup.emission)");
    l.volumes = readVolumeNames(o, "volumes");
    l.shadow_volumes = readVolumeNames(o, "shadow_volumes");
    l.enabled = o.boolean("enabled", true);
    if (l.type == LightType::Point || l.type == LightType::Spot) l.position = readPoint(o, "position");
    if (l.type == LightType::Directional || l.type == LightType::Spot) l.direction = readDirection(o, "direction");
    l.color = o.vec3("color", l.color);
    if (!(glm::all(glm::greaterThanEqual(l.color, glm::vec3(0.0f))) && std::isfinite(l.color.x + l.color.y + l.color.z)))
        o.fail("color", "must be finite and >= 0");
    l.intensity = o.number("intensity", l.intensity);
    if (!(l.intensity >= 0) || !std::isfinite(l.intensity)) o.fail("intensity", "must be a finite number >= 0");
    l.cone_angle = o.number("cone_angle", l.cone_angle);
    if (!(l.cone_angle > 0 && l.cone_angle < 90)) o.fail("cone_angle", "must lie in (0, 90) degrees");
    l.cone_softness = o.number("cone_softness", l.cone_softness);
    if (!(l.cone_softness >= 0 && l.cone_softness <= l.cone_angle))
        o.fail("cone_softness", "must lie in [0, cone_angle]");
    if (l.type == LightType::Environment) l.environment = readEnvironment(o, base_dir);
    return l;
}

namespace {

Holdout readHoldout(const JsonObject& o, const std::string& base_dir) {
    Holdout h;
    if (o.has("mesh")) {
        if (o.has("depth")) o.fail("depth", "a holdout is a depth image or a mesh, not both");
        o.rejectUnknown({"mesh", "transform", "voxel_size", "shadow_reach"});
        h.mesh = resolvePath(o.string("mesh"), base_dir);
        if (!isMeshFile(h.mesh)) o.fail("mesh", "not a mesh file voxlux reads (expected .obj, .gltf, .glb or .fbx)");
        if (o.has("transform")) h.transform = readVolumeTransform(o, base_dir);
        h.voxel_size = o.number("voxel_size", h.voxel_size);
        if (!(h.voxel_size >= 0.0f) || !std::isfinite(h.voxel_size))
            o.fail("voxel_size", "must be a finite length >= 0 in world units (0: the volumes' finest voxel)");
        if (o.has("shadow_reach")) {
            h.shadow_reach = o.number("shadow_reach");
            if (!(*h.shadow_reach >= 0.0f) || !std::isfinite(*h.shadow_reach)) o.fail("shadow_reach", "must be a finite length >= 0 in world units");
        }
        return h;
    }
    o.rejectUnknown({"depth", "channel", "ray_distance"});
    if (!o.has("depth")) o.fail("depth", "a holdout needs a depth image (\"depth\") or a mesh (\"mesh\")");
    h.depth = resolvePath(o.string("depth"), base_dir);
    h.channel = o.string("channel", h.channel);
    if (h.channel.empty()) o.fail("channel", "must name a channel of the depth image");
    h.ray_distance = o.boolean("ray_distance", h.ray_distance);
    return h;
}

// The emission sources at `o`'s "emission", if any.
std::vector<EmissionSource> readEmission(const JsonObject& o) {
    std::vector<EmissionSource> out;
    if (!o.has("emission")) return out;
    const auto sources = o.objects("emission");
    if (sources.size() > VX_MAX_EMISSION)
        o.fail("emission", "at most " + std::to_string(VX_MAX_EMISSION) + " sources (got " + std::to_string(sources.size()) + ")");
    for (const auto& e : sources) out.push_back(readEmissionSource(e));
    return out;
}

// A name holds letters, digits, '_' and '-': it becomes part of EXR channel names, where '.'
// separates layers.
bool isNameCharacter(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; }

// A volume's name when it has none: its file's, without the folder, the extension and the frame
// pattern ("fire.####.vdb" -> "fire"), other characters turned to '_'.
std::string nameFromPath(const std::string& path) {
    std::string stem = fs::path(path).stem().string();
    stem.erase(std::remove(stem.begin(), stem.end(), '#'), stem.end());
    for (char& c : stem)
        if (!isNameCharacter(c)) c = '_';
    while (!stem.empty() && (stem.back() == '_' || stem.back() == '-')) stem.pop_back();
    return stem.empty() ? "volume" : stem;
}

// `volumes`, or `volume` with `material` and `emission` beside it (a list of one); each named,
// the names unique.
std::vector<VolumeSpec> readVolumes(const JsonObject& root, const std::string& base_dir) {
    std::vector<VolumeSpec> volumes;
    std::vector<JsonObject> entries;
    if (root.has("volumes")) {
        if (root.has("volume")) root.fail("volume", "goes alone, with material and emission beside it, or as an entry of volumes: not both");
        for (const char* key : {"material", "emission"})
            if (root.has(key)) root.fail(key, "goes in each entry of volumes");
        entries = root.objects("volumes");
        if (entries.empty()) root.fail("volumes", "expected at least one volume");
        std::vector<std::string> keys = kVolumeKeys;
        keys.insert(keys.end(), {"material", "emission"});
        for (const JsonObject& o : entries) {
            o.rejectUnknown(keys);
            VolumeSpec v = readVolume(o, base_dir);
            if (o.has("material")) v.material = readMaterial(o.object("material"));
            v.emission = readEmission(o);
            volumes.push_back(std::move(v));
        }
    } else {
        entries.push_back(root.object("volume"));
        entries[0].rejectUnknown(kVolumeKeys);
        VolumeSpec v = readVolume(entries[0], base_dir);
        if (root.has("material")) v.material = readMaterial(root.object("material"));
        v.emission = readEmission(root);
        volumes.push_back(std::move(v));
    }
    for (size_t i = 0; i < volumes.size(); ++i) {
        const JsonObject& o = entries[i];
        VolumeSpec& v = volumes[i];
        if (!v.material.transfer_2d.empty() && v.color)
            o.fail("color", "the 2D transfer function (material.transfer_function_2d) gives the albedo; remove color");
        v.name = o.has("name") ? o.string("name") : nameFromPath(v.path);
        if (v.name.empty() || !std::all_of(v.name.begin(), v.name.end(), isNameCharacter))
            o.fail("name", "'" + v.name + "' must be letters, digits, '_' and '-'");
        for (size_t k = 0; k < i; ++k)
            if (volumes[k].name == v.name)
                o.fail("name", "'" + v.name + "' is also volume " + std::to_string(k) + "'s name" +
                                   (o.has("name") ? "" : " (taken from the file's; set name)"));
    }
    const std::string list = root.has("volumes") ? "volumes" : "volume";
    if (std::none_of(volumes.begin(), volumes.end(), [](const VolumeSpec& v) { return v.enabled; }))
        root.fail(list, "every volume is disabled (enabled: false): a scene renders one at least");
    // What the march through several volumes (shaders/vx_volumes.h) does not read yet: each
    // volume is its density grid under its material (a 1D transfer function too), its colour
    // grid, and the light its grids emit. Disabled volumes are not rendered, so they take anything.
    size_t placed = 0, sources = 0;
    bool roles = false;
    for (size_t i = 0; i < volumes.size(); ++i) {
        const VolumeSpec& v = volumes[i];
        if (!v.enabled) continue;
        placed += std::max<size_t>(1, v.instances.size());
        roles |= v.role != VolumeRole::Visible;
        sources += v.emission.size();
        if (sources > VX_MAX_EMISSION)
            entries[i].fail("emission", "brings the scene's emission sources to " + std::to_string(sources) + ": the volumes take at most " +
                                            std::to_string(VX_MAX_EMISSION) + " together");
    }
    if (placed > VX_MAX_VOLUMES)
        root.fail(list, std::to_string(placed) + " volumes and instances: a scene places at most " + std::to_string(VX_MAX_VOLUMES) + " so far");
    if (placed > 1 || roles)
        for (size_t i = 0; i < volumes.size(); ++i)
            if (volumes[i].enabled && !volumes[i].material.transfer_2d.empty())
                entries[i].object("material").fail("transfer_function_2d",
                                                   "set: a volume of several takes a 1D transfer function (transfer_function) only, so far");
    return volumes;
}

}  // namespace

Scene parseScene(const std::string& text, const std::string& file, const std::string& base_dir) {
    return sceneFromJson(parseJson(text, file), file, base_dir);
}

Scene sceneFromJson(const nlohmann::json& json, const std::string& file, const std::string& base_dir) {
    JsonObject root(json, file, "");
    root.rejectUnknown({"volume", "volumes", "material", "lights", "holdouts", "camera", "render", "effects", "emission", "color", "output"});
    Scene s;
    s.volumes = readVolumes(root, base_dir);
    if (root.has("lights"))
        for (const auto& l : root.objects("lights")) s.lights.push_back(readLight(l, base_dir));
    for (size_t i = 0; i < s.lights.size(); ++i)
        for (const auto& [key, names] : {std::pair{"volumes", s.lights[i].volumes}, std::pair{"shadow_volumes", s.lights[i].shadow_volumes}})
            for (const std::string& name : names.value_or(std::vector<std::string>{}))
                if (std::none_of(s.volumes.begin(), s.volumes.end(), [&](const VolumeSpec& v) { return v.name == name; }))
                    root.element("lights", i).fail(key, "no volume is named '" + name + "' (" + volumeNamesText(s.volumes) + ")");
    if (const size_t sets = lightLinks(s).sets.size(); sets > VX_MAX_LINK_SETS)
        root.fail("lights", "link " + std::to_string(sets) + " different pairs of volumes and shadow_volumes: a scene takes at most " +
                                std::to_string(VX_MAX_LINK_SETS) + " so far");
    if (root.has("holdouts"))
        for (const auto& h : root.objects("holdouts")) s.holdouts.push_back(readHoldout(h, base_dir));
    if (root.has("camera")) s.camera = readCamera(root.object("camera"), base_dir);
    if (root.has("render")) s.render = readRender(root.object("render"));
    if (root.has("effects")) s.effects = readEffects(root.object("effects"));
    if (s.render.method == RenderMethod::Reference && (s.effects.surface || s.effects.perturbation))
        root.fail("effects", "surface and perturbation are march-only effects (render.method is \"reference\")");
    if (root.has("color")) s.color = readColor(root.object("color"), base_dir);
    if (root.has("output")) s.output = readOutput(root.object("output"));
    if (s.render.method == RenderMethod::Reference && s.output.deep)
        root.fail("output", "deep is a march-only output (render.method is \"reference\"): the Monte Carlo reference writes no deep samples");
    if (const Scene rendered = renderedScene(s); rendersAsSeveral(rendered)) {
        const bool meshes = std::any_of(s.holdouts.begin(), s.holdouts.end(), [](const Holdout& h) { return !h.mesh.empty(); });
        const size_t placed = placedVolumeCount(withEnabledVolumes(s));
        const std::string why = meshes ? " with a mesh holdout: its shadowing cells make the scene one of several volumes, which render without it, so far"
                                : placed > 1           ? " with " + std::to_string(placed) + " volumes: several volumes render without it, so far"
                                : linksLights(rendered) ? " with linked lights: a linked scene renders as several volumes, which render without it, so far"
                                                        : " with a volume of role \"" + kVolumeRoleNames[size_t(rendered.volume().role)] +
                                                 "\": it renders as one of several volumes, which render without it, so far";
        if (s.effects.surface) root.object("effects").fail("surface", "set" + why);
        if (s.effects.perturbation) root.object("effects").fail("perturbation", "set" + why);
        // Kniss's transport colour holds for any medium; the diffusion profile is one material's.
        if (s.effects.indirect && s.effects.indirect->model == IndirectModel::Diffusion)
            for (const VolumeSpec& v : rendered.volumes)
                if (!v.holdout_mesh &&
                    (v.material.albedo != rendered.volume().material.albedo || v.material.anisotropy != rendered.volume().material.anisotropy))
                    root.object("effects").fail("indirect", "the diffusion model takes its profile from one material, and volume '" + v.name +
                                                                "' has another albedo or anisotropy than '" + rendered.volume().name +
                                                                "': give them one, or take the kniss model (transport_color)");
    }
    if (s.output.deep && std::any_of(s.volumes.begin(), s.volumes.end(), [](const VolumeSpec& v) { return v.enabled && v.role != VolumeRole::Visible; }))
        root.fail("output", "deep output with a volume of role matte or shadow_only: its deep samples would carry every volume's opacity, so far");
    if (s.output.deep && std::any_of(s.holdouts.begin(), s.holdouts.end(), [](const Holdout& h) { return !h.mesh.empty(); }))
        root.fail("output", "deep output with a mesh holdout: its shadowing cells are a shadow_only volume, whose opacity the deep samples "
                            "would carry, so far; hold the deep render out with the mesh's depth image");
    if (s.output.deep && !lightGroups(s).names.empty())
        root.fail("output", "deep output with the light_groups AOV: the deep samples carry the beauty alone, so far; write the groups in a render of their own");
    if (s.render.motion_blur && s.output.deep)
        root.fail("output", "deep output is made at one time and render.motion_blur spreads a pixel over the shutter: turn one of them off");
    if (s.camera && s.camera->fstop > 0.0f && s.output.deep)
        root.fail("output", "deep output is made through a pinhole and camera.fstop spreads a pixel over the lens: turn one of them off");
    return s;
}

Scene loadSceneFile(const std::string& path) {
    return parseScene(readFileText(path, "scene file"), path, fs::path(path).parent_path().string());
}

}  // namespace voxlux
