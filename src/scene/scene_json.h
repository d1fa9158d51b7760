// Scene <-> JSON (docs/scene.md): reading and validating (scene_read.cpp), writing
// (scene_write.cpp) and `--set` edits of the JSON before it is read (scene_set.cpp); and the
// helpers the lighting methods' settings read and write theirs with (readOptional, jsonDecimal).
#pragma once
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/json_reader.h"
#include "scene/scene.h"

namespace voxlux {

// Reads and validates a scene file. Relative volume paths are resolved against the scene
// file's folder. Throws InputError naming the file and the JSON pointer of the bad key.
Scene loadSceneFile(const std::string& path);
Scene parseScene(const std::string& text, const std::string& file, const std::string& base_dir);
// The same, from parsed JSON: strings stay bytes (a Latin-1 file name), never re-encoded as text.
Scene sceneFromJson(const nlohmann::json& json, const std::string& file, const std::string& base_dir);

// An optional effect: `true` takes the defaults, `false` turns it off, an object sets its knobs.
template <class T>
std::optional<T> readOptional(const JsonObject& o, const std::string& key, T (*read)(const JsonObject&)) {
    const auto& v = o.raw(key);
    if (v.is_boolean()) return v.get<bool>() ? std::optional<T>(read(JsonObject(nlohmann::json::object(), "", ""))) : std::nullopt;
    if (!v.is_object()) o.fail(key, "expected true, false or an object");
    return read(o.object(key));
}

// Floats as the shortest decimal that reads back to the same float (0.9f writes as 0.9), as the
// scene's JSON and its hashes hold them.
double jsonDecimal(float f);
nlohmann::json jsonVec3(glm::vec3 v);

// One light of a scene's "lights" array, and back.
Light readLight(const JsonObject& o, const std::string& base_dir = "");
nlohmann::json lightToJson(const Light& light);
// A matrix as 16 numbers, column-major (camera.matrix), and back (of a render document's, unchecked).
nlohmann::json matrixToJson(const glm::mat4& m);
glm::mat4 matrixFromJson(const nlohmann::json& j);
// A volume's transform as `transform` writes it (a .chan file as its name).
nlohmann::json volumeTransformToJson(const VolumeTransform& t);

// "auto", "x", "y" or "z", as volume.up spells it.
const char* upAxisName(UpAxis up);

// The JSON a scene file would need to reproduce `scene` (used by `voxlux scene`).
nlohmann::json sceneToJson(const Scene& scene);

// `scene` with the paths a scene file resolves against its folder (volume, colour config, grade
// files) made relative to `folder`, so the scene reads back the same when saved there.
Scene scenePathsRelativeTo(Scene scene, const std::string& folder);

// Sets one dotted key of a scene's JSON from "KEY=VALUE", as `--set effects.cone.samples=50` does.
// Throws InputError quoting `set` when it has no '=' or an empty key.
void applySceneSet(nlohmann::json& scene, const std::string& set);

// The set that turns on the effect at dotted `key` ("effects.indirect"): "KEY=true", or
// "KEY=<the scene's object>" when the scene already has settings for it, so they are kept.
std::string effectOnSet(const nlohmann::json& scene, const std::string& key);

}  // namespace voxlux
