// Scene files: validation messages name the file and the JSON pointer of the bad key.
#include <algorithm>
#include <sstream>

#include "core/error.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

TEST(Scene, MinimalSceneGetsDefaults) {
    Scene s = parseScene(R"({"volume": {"path": "smoke.vdb"}})", "shot.json", "/shots");
    EXPECT_EQ(s.volume().path, "/shots/smoke.vdb");
    EXPECT_EQ(s.volume().density, (GridRef{"density", 0}));
    EXPECT_FALSE(s.camera.has_value());
    EXPECT_EQ(s.render.width, 512);
    EXPECT_FLOAT_EQ(s.render.step, 0.5f);
    EXPECT_EQ(s.effects.shadows, ShadowMethod::Raymarch);
}

TEST(Scene, ErrorsNameTheKeyAndItsPath) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "lights": [{"type": "area"}]})"),
              "shot.json: /lights/0/type: 'area' is not one of directional, point, spot, ambient, environment");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "lights": [{}, {"intensity": "lots", "direction": [0,0,1]}]})"),
              "shot.json: /lights/0/direction: required key is missing");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "render": {"stepp": 0.5}})"),
              "shot.json: /render/stepp: unknown key (expected one of resolution, step, shadow_step, "
              "transmittance_cutoff, exposure, filter, backend, method, reference, motion_blur, region)");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "render": {"filter": "cubic"}})"),
              "shot.json: /render/filter: 'cubic' is not one of trilinear, tricubic");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "render": {"resolution": [512]}})"),
              "shot.json: /render/resolution: expected an array of 2 numbers");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "material": {"albedo": [1.5, 0, 0]}})"),
              "shot.json: /material/albedo: each component must lie in [0, 1]");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "camera": {"position": [0,0,0], "look_at": [0,0,0]}})"),
              "shot.json: /camera/look_at: must differ from position");
    EXPECT_EQ(sceneErrorOf(R"({"material": {}})"), "shot.json: /volume: required key is missing");
    EXPECT_EQ(sceneErrorOf(R"([1, 2])"), "shot.json: /: expected an object, got array");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb", "density": {"name": "d", "index": -1}}})"),
              "shot.json: /volume/density/index: must be 0 or more");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "output": {"aovs": ["direct", "beauty"]}})"),
              "shot.json: /output/aovs: unknown AOV 'beauty' (expected direct, ambient, indirect, emission, transmittance, depth, variance, coverage or light_groups)");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"light_resolution": 1}})"),
              "shot.json: /effects/light_resolution: must lie in 2..1024 cells");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "lights": [{"type": "ambient", "position": [0, 0, 0]}]})"),
              "shot.json: /lights/0/position: unknown key (expected one of name, enabled, type, color, intensity, group)");
}

// Values a float or an int cannot hold, and cameras or lights a ray cannot be traced from, are
// refused with their key.
TEST(Scene, NumbersBeyondTheirTypeAndDegenerateCamerasAreRefused) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "lights": [{"direction": [1e308, 1, 1]}]})"),
              "shot.json: /lights/0/direction: 1e+308 is beyond the float range (+-3.4e38)");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "render": {"step": 1e400}})"),
              "shot.json: malformed JSON: number overflow parsing '1e400'");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"cone": {"samples": -4294967296}}})"),
              "shot.json: /effects/cone/samples: -4294967296 is beyond the int range");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "camera": {"position": [3e38, 0, 0], "look_at": [0, 0, 0]}})"),
              "shot.json: /camera/position: each coordinate must lie within +-1e9");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 3.4e38]}})"),
              "shot.json: /camera/look_at: each coordinate must lie within +-1e9");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "camera": {"matrix": [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,0]}})"),
              "shot.json: /camera/matrix: its rotation part (elements 0-10) must be invertible");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "camera": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 5e9,0,0,1]}})"),
              "shot.json: /camera/matrix: the position (elements 12-14) must lie within +-1e9");
    // A huge or tiny direction is a direction: normalised without overflow or underflow.
    for (const char* d : {"[1e30, 1e30, 1e30]", "[1e-40, 1e-40, 1e-40]"}) {
        const Scene s = parseScene(std::string(R"({"volume": {"path": "a.vdb"}, "lights": [{"direction": )") + d + "}]}",
                                   "shot.json", "/shots");
        EXPECT_NEAR(s.lights[0].direction.x, 1 / std::sqrt(3.0f), 1e-6f) << d;
        EXPECT_NEAR(glm::length(s.lights[0].direction), 1.0f, 1e-6f) << d;
    }
}

TEST(Scene, MalformedJsonGivesLineAndColumn) {
    EXPECT_EQ(sceneErrorOf("{\n  \"volume\": {\"path\": \"a.vdb\"},\n  \"render\": {\"step\": 0.5,}\n}"),
              "shot.json: malformed JSON at line 3, column 26: unexpected '}'; expected string literal");
}

// Nesting past 64 levels is refused before any parser recurses: 100,000 levels used to overflow
// the stack.
TEST(Scene, NestingDeeperThan64LevelsIsRefused) {
    const auto nested = [](int depth) { return std::string(depth, '[') + std::string(depth, ']'); };
    EXPECT_NO_THROW(checkJsonDepth(nested(64), "f.json"));
    EXPECT_EQ(inputErrorOf([&] { checkJsonDepth(nested(65), "f.json"); }), "f.json: JSON nested deeper than 64 levels at line 1");
    EXPECT_EQ(inputErrorOf([&] { checkJsonDepth("{\n\"a\": \n" + nested(1000), "f.json"); }),
              "f.json: JSON nested deeper than 64 levels at line 3");
    // Brackets in strings, escaped quotes included, are text.
    EXPECT_NO_THROW(checkJsonDepth("[\"" + nested(100) + "\\\"" + std::string(100, '{') + "\"]", "f.json"));

    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "output": {"aovs": )" + nested(100000) + "}}"),
              "shot.json: JSON nested deeper than 64 levels at line 1");
    nlohmann::json scene = {{"volume", {{"path", "a.vdb"}}}};
    EXPECT_EQ(inputErrorOf([&] { applySceneSet(scene, "render.step=" + nested(5000)); }),
              "--set render.step: JSON nested deeper than 64 levels at line 1");
}

// Keys and hashes take file names as bytes: what is not UTF-8 is written as \xHH, distinctly.
TEST(Scene, JsonTextEscapesBytesThatAreNotUtf8) {
    const std::string utf8 = "caf\xc3\xa9.vdb", latin1 = "caf\xe9.vdb";
    EXPECT_EQ(jsonText(nlohmann::json{{"path", utf8}}), "{\"path\":\"" + utf8 + "\"}");
    EXPECT_EQ(jsonText(nlohmann::json{{"path", latin1}, {"n", 1}}), "{\"n\":1,\"path\":\"caf\\\\xE9.vdb\"}");
    EXPECT_NE(jsonText(nlohmann::json(latin1)), jsonText(nlohmann::json("caf\xe8.vdb")));
}

// volume.frames: [first, last], or a farm's spec as a string, written back in the form read.
TEST(Scene, FramesAreARangeOrASpec) {
    const Scene range = parseScene(R"({"volume": {"path": "f_####.vdb", "frames": [1, 60]}})", "shot.json", "");
    EXPECT_EQ(sceneToJson(range)["volumes"][0]["frames"], nlohmann::json::array({1, 60}));
    const Scene spec = parseScene(R"({"volume": {"path": "f_####.vdb", "frames": "1-60x2,100"}})", "shot.json", "");
    EXPECT_EQ(spec.volume().frames->count(), 31);
    EXPECT_EQ(sceneToJson(spec)["volumes"][0]["frames"], "1-59x2,100");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb", "frames": "1-60x"}})"),
              "shot.json: /volume/frames: expected FIRST-LAST[xSTEP] or a list of them, e.g. 1-240x2,300");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb", "frames": [5, 1]}})"),
              "shot.json: /volume/frames: expected [first, last] integers with first <= last, or a string such as \"1-240x2,300\"");
}

TEST(Scene, RoundTripThroughJson) {
    Scene s = parseScene(R"({
        "volume": {"path": "fire_####.vdb", "frames": [1, 60], "density": {"name": "density", "index": 2},
                   "color": "Cd", "level_set": "fog", "up": "z"},
        "material": {"density_scale": 2.5, "density_units": "voxel", "albedo": [0.5, 0.6, 0.7], "anisotropy": 0.3,
                     "transfer_function": [{"value": 0, "extinction": 0}, {"value": 100, "extinction": 1, "albedo": [1, 0.5, 0.2]}]},
        "lights": [{"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0], "intensity": 40, "cone_angle": 25}],
        "camera": {"position": [0, 1, 10], "look_at": [0, 1, 0], "fov": 35},
        "render": {"resolution": [320, 240], "step": 0.25, "exposure": 1.5, "filter": "tricubic", "backend": "cpu"},
        "effects": {"shadows": "sat_cone", "ambient_occlusion": {"shells": 7, "radius": 1.5}, "color_bleeding": true,
                    "cone": {"angle": 4, "samples": 30, "growth": 0.2}, "light_resolution": 96, "light_memory_mb": 512,
                    "propagation": {"filter": "trilinear"}},
        "output": {"path": "out_####.exr", "pixel_type": "float", "aovs": ["depth", "ambient"], "deep": true, "deep_samples": 8}})",
                         "shot.json", "");
    // Every key, as written by hand from the scene above and the defaults of docs/scene.md.
    // The one volume is written as the list `volumes`, named from its file, with its material
    // and emission inside.
    const nlohmann::json expected = nlohmann::json::parse(R"({
        "volumes": [{"name": "fire", "path": "fire_####.vdb", "frames": [1, 60], "density": {"name": "density", "index": 2},
                     "color": "Cd", "level_set": "fog", "up": "z", "role": "visible",
                     "material": {"density_scale": 2.5, "density_units": "voxel", "albedo": [0.5, 0.6, 0.7], "anisotropy": 0.3,
                                  "transfer_function": [{"value": 0, "extinction": 0, "albedo": [1, 1, 1]},
                                                        {"value": 100, "extinction": 1, "albedo": [1, 0.5, 0.2]}]},
                     "emission": []}],
        "lights": [{"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0], "color": [1, 1, 1], "intensity": 40,
                    "cone_angle": 25, "cone_softness": 5}],
        "camera": {"fov": 35, "position": [0, 1, 10], "look_at": [0, 1, 0], "up": [0, 1, 0]},
        "render": {"resolution": [320, 240], "step": 0.25, "shadow_step": 1, "transmittance_cutoff": 0.0001,
                   "exposure": 1.5, "filter": "tricubic", "backend": "cpu", "method": "march",
                   "reference": {"spp": 64, "max_bounces": 16, "seed": 1, "roulette_depth": 3}, "motion_blur": false},
        "effects": {"shadows": "sat_cone", "ambient_occlusion": {"shells": 7, "radius": 1.5}, "color_bleeding": 1,
                    "cone": {"angle": 4, "samples": 30, "growth": 0.2},
                    "propagation": {"blend_axes": false, "eye_pass": false, "chroma_subsampling": false, "coherent": true,
                                    "filter": "trilinear"},
                    "indirect": false, "surface": false, "perturbation": false,
                    "light_resolution": 96, "light_memory_mb": 512},
        "color": {},
        "output": {"path": "out_####.exr", "pixel_type": "float", "compression": "zip", "aovs": ["depth", "ambient"],
                   "deep": true, "deep_samples": 8}})");
    EXPECT_EQ(sceneToJson(s), expected) << sceneToJson(s).dump(2);
    // And the reader takes back every key the writer writes.
    const Scene again = parseScene(expected.dump(), "again.json", "");
    EXPECT_EQ(sceneToJson(again), expected);
    EXPECT_EQ(again.volume().density.index, 2);
    EXPECT_EQ(again.lights[0].type, LightType::Spot);
    EXPECT_FLOAT_EQ(again.volume().material.transfer[1].albedo.z, 0.2f);
    EXPECT_EQ(again.render.filter, Filter::Tricubic);
    EXPECT_EQ(again.effects.shadows, ShadowMethod::SatCone);
    EXPECT_EQ(again.effects.ambient_occlusion->shells, 7);
    EXPECT_EQ(again.effects.color_bleeding, 1.0f);
    EXPECT_EQ(again.effects.cone.samples, 30);
    EXPECT_EQ(again.effects.light_resolution, 96);
}

// AOVs are names or {"name", "pixel_type"} objects; JSON keeps the short form where it can.
TEST(Scene, OutputAovsWithPixelTypesAndCompressions) {
    Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "output": {"compression": "dwab",
        "aovs": ["direct", {"name": "emission", "pixel_type": "float"}, {"name": "depth"}]}})",
                         "shot.json", "");
    ASSERT_EQ(s.output.aovs.size(), 3u);
    EXPECT_EQ(s.output.aovs[0], (AovSpec{"direct", std::nullopt}));
    EXPECT_EQ(s.output.aovs[1], (AovSpec{"emission", PixelType::Float}));
    EXPECT_EQ(s.output.aovs[2], (AovSpec{"depth", std::nullopt}));
    EXPECT_EQ(s.output.compression, "dwab");
    EXPECT_EQ(sceneToJson(s)["output"].dump(),
              R"({"aovs":["direct",{"name":"emission","pixel_type":"float"},"depth"],"compression":"dwab","deep":false,"deep_samples":16,"pixel_type":"half"})");
    for (const std::string& c : knownCompressions())
        EXPECT_EQ(parseScene(R"({"volume": {"path": "a.vdb"}, "output": {"compression": ")" + c + R"("}})", "s.json", "")
                      .output.compression,
                  c);
}

TEST(Scene, OutputAovsAndCompressionAreValidated) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "output": {"deep_samples": 65}})"),
              "shot.json: /output/deep_samples: must lie in 1..64");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "output": {"deep": "yes"}})"),
              "shot.json: /output/deep: expected true or false, got string");
    const std::string v = R"({"volume": {"path": "a.vdb"}, "output": )";
    EXPECT_EQ(sceneErrorOf(v + R"({"compression": "b44"}})"),
              "shot.json: /output/compression: 'b44' is not one of none, zip, zips, piz, dwaa, dwab, rle");
    EXPECT_EQ(sceneErrorOf(v + R"({"aovs": "direct"}})"), "shot.json: /output/aovs: expected an array of AOV names or objects");
    EXPECT_EQ(sceneErrorOf(v + R"({"aovs": [3]}})"),
              "shot.json: /output/aovs: unknown AOV '3' (expected direct, ambient, indirect, emission, transmittance, depth, variance, coverage or light_groups)");
    EXPECT_EQ(sceneErrorOf(v + R"({"aovs": ["direct", {"name": "beauty"}]}})"),
              "shot.json: /output/aovs/1/name: unknown AOV 'beauty' (expected direct, ambient, indirect, emission, "
              "transmittance, depth, variance, coverage or light_groups)");
    EXPECT_EQ(sceneErrorOf(v + R"({"aovs": [{"pixel_type": "float"}]}})"), "shot.json: /output/aovs/0/name: required key is missing");
    EXPECT_EQ(sceneErrorOf(v + R"({"aovs": [{"name": "depth", "pixel_type": "double"}]}})"),
              "shot.json: /output/aovs/0/pixel_type: 'double' is not one of half, float");
    EXPECT_EQ(sceneErrorOf(v + R"({"aovs": [{"name": "depth", "type": "float"}]}})"),
              "shot.json: /output/aovs/0/type: unknown key (expected one of name, pixel_type)");
    EXPECT_EQ(sceneErrorOf(v + R"({"aovs": ["direct", "depth", {"name": "direct", "pixel_type": "float"}]}})"),
              "shot.json: /output/aovs/2: duplicate AOV 'direct' (first at /output/aovs/0)");
}

// The effects keys are the march's own and each lighting method's (MethodSettings): each has one
// owner, the reader takes exactly the keys the writer writes, and a key no one owns is refused
// with all of them.
TEST(Scene, EveryEffectsKeyHasOneOwnerAndIsWritten) {
    const std::string refusal = sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"shadow": "none"}})");
    EXPECT_EQ(refusal, "shot.json: /effects/shadow: unknown key (expected one of shadows, surface, perturbation, light_resolution, "
                       "light_memory_mb, ambient_occlusion, color_bleeding, cone, propagation, indirect)");
    const std::string listed = refusal.substr(refusal.find("one of ") + 7, refusal.size() - refusal.find("one of ") - 8);
    std::vector<std::string> read;
    std::stringstream in(listed);
    for (std::string key; std::getline(in, key, ',');) read.push_back(key.substr(key.find_first_not_of(' ')));
    std::sort(read.begin(), read.end());
    EXPECT_EQ(std::adjacent_find(read.begin(), read.end()), read.end()) << "an effects key with two owners";
    const nlohmann::json effects = sceneToJson(parseScene(R"({"volume": {"path": "a.vdb"}})", "shot.json", ""))["effects"];
    std::vector<std::string> written;
    for (const auto& [key, value] : effects.items()) written.push_back(key);
    EXPECT_EQ(read, written);   // items() are sorted
    for (const std::string& key : methodSettingKeys()) EXPECT_TRUE(std::binary_search(read.begin(), read.end(), key)) << key;
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"shadows": "cones"}})"),
              "shot.json: /effects/shadows: 'cones' is not one of none, raymarch, sat_cone, propagation");
}

TEST(Scene, AmbientOcclusionAndLightsDefaults) {
    Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "lights": [{"type": "ambient", "intensity": 0.5}],
                             "effects": {"ambient_occlusion": true}})",
                         "shot.json", "");
    EXPECT_EQ(s.lights[0].type, LightType::Ambient);
    ASSERT_TRUE(s.effects.ambient_occlusion.has_value());
    EXPECT_EQ(s.effects.ambient_occlusion->shells, 3);
    EXPECT_EQ(s.effects.ambient_occlusion->radius, 0.0f);
    EXPECT_EQ(s.effects.light_resolution, 128);
    EXPECT_FALSE(parseScene(R"({"volume": {"path": "a.vdb"}, "effects": {"ambient_occlusion": false}})", "s.json", "")
                     .effects.ambient_occlusion.has_value());
}

TEST(Scene, PropagationEffectsRoundTripAndDefaults) {
    Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "effects": {"shadows": "propagation",
        "propagation": {"eye_pass": true, "chroma_subsampling": true},
        "indirect": {"angle": 40, "samples": 13, "phase": "henyey_greenstein", "g": 0.7, "transport_color": [1, 0.5, 0.25]},
        "surface": {"gradient_low": 0.1, "gradient_high": 0.3},
        "perturbation": {"seed": 7, "scale": 2, "octaves": 4, "density": 0.5, "displacement": 1.5, "velocity": [0.1, 0, 0]}}})",
                         "shot.json", "");
    const nlohmann::json expected_effects = nlohmann::json::parse(R"({
        "shadows": "propagation", "ambient_occlusion": false, "color_bleeding": 0,
        "cone": {"angle": 2, "samples": 20, "growth": 0.05},
        "propagation": {"blend_axes": false, "eye_pass": true, "chroma_subsampling": true, "coherent": true, "filter": "tricubic"},
        "indirect": {"model": "kniss", "strength": 1, "angle": 40, "samples": 13, "phase": "henyey_greenstein", "exponent": 4,
                     "g": 0.7, "transport_color": [1, 0.5, 0.25]},
        "surface": {"gradient_low": 0.1, "gradient_high": 0.3, "specular": 0.5, "shininess": 32},
        "perturbation": {"seed": 7, "scale": 2, "octaves": 4, "lacunarity": 2, "gain": 0.5, "density": 0.5,
                         "transport": 0, "displacement": 1.5, "velocity": [0.1, 0, 0], "time": 0},
        "light_resolution": 128, "light_memory_mb": 2048})");
    EXPECT_EQ(sceneToJson(s)["effects"], expected_effects) << sceneToJson(s)["effects"].dump(2);
    nlohmann::json written = sceneToJson(s);
    written["effects"] = expected_effects;
    const Scene again = parseScene(written.dump(), "again.json", "");
    EXPECT_EQ(sceneToJson(again)["effects"], expected_effects);
    EXPECT_EQ(again.effects.shadows, ShadowMethod::Propagation);
    EXPECT_FALSE(again.effects.propagation.blend_axes);
    EXPECT_TRUE(again.effects.propagation.eye_pass);
    ASSERT_TRUE(again.effects.indirect.has_value());
    EXPECT_EQ(s.effects.indirect->model, IndirectModel::Kniss);   // implied by the transport colour
    EXPECT_EQ(again.effects.indirect->model, IndirectModel::Kniss);
    EXPECT_EQ(again.effects.indirect->phase, BlurPhase::HenyeyGreenstein);
    EXPECT_EQ(again.effects.indirect->samples, 13);
    EXPECT_FLOAT_EQ(again.effects.indirect->transport_color.z, 0.25f);
    EXPECT_FLOAT_EQ(again.effects.indirect->strength, 1.0f);
    EXPECT_FLOAT_EQ(again.effects.surface->gradient_high, 0.3f);
    EXPECT_EQ(again.effects.perturbation->seed, 7);
    EXPECT_EQ(again.effects.perturbation->octaves, 4);
    EXPECT_FLOAT_EQ(again.effects.perturbation->velocity.x, 0.1f);
    // `true` takes every default; absent or `false` is off.
    Scene d = parseScene(R"({"volume": {"path": "a.vdb"}, "effects": {"indirect": true, "perturbation": false}})",
                         "shot.json", "");
    EXPECT_EQ(d.effects.indirect->samples, 9);
    EXPECT_EQ(d.effects.indirect->model, IndirectModel::Diffusion);
    EXPECT_FALSE(sceneToJson(d)["effects"]["indirect"].contains("transport_color"));
    EXPECT_FALSE(d.effects.perturbation.has_value());
    EXPECT_FALSE(d.effects.surface.has_value());
}

TEST(Scene, SurfaceAndPerturbationAreValidated) {
    const std::string v = R"({"volume": {"path": "a.vdb"}, "effects": )";
    EXPECT_EQ(sceneErrorOf(v + R"({"surface": {"gradient_low": 0.5, "gradient_high": 0.2}}})"),
              "shot.json: /effects/surface/gradient_high: needs 0 <= gradient_low < gradient_high");
    EXPECT_EQ(sceneErrorOf(v + R"({"perturbation": {"octaves": 0}}})"),
              "shot.json: /effects/perturbation/octaves: must lie in 1..8");
    EXPECT_EQ(sceneErrorOf(v + R"({"perturbation": {"displacement": -1}}})"),
              "shot.json: /effects/perturbation/displacement: must lie in [0, 64] voxels");
}

// The emission list: every kind, its defaults and the round trip.
TEST(EmissionScene, ParsesEveryKindAndRoundTrips) {
    const Scene s = parseScene(R"({"volume": {"path": "fire.vdb"}, "emission": [
        {"grid": "flame"},
        {"grid": {"name": "temperature", "index": 1}, "kind": "blackbody", "intensity": 2, "temperature_scale": 1000,
         "temperature_offset": -100, "cutoff": 900, "normalization": "physical", "reference_temperature": 1800},
        {"grid": "heat", "kind": "blackbody"},
        {"grid": "flame", "kind": "ramp", "ramp": [{"value": 0, "color": [0, 0, 0]}, {"value": 2, "color": [4, 2, 1]}]}]})",
                               "shot.json", "");
    ASSERT_EQ(s.volume().emission.size(), 4u);
    EXPECT_EQ(s.volume().emission[0].kind, EmissionKind::Constant);   // the default kind, colour and intensity
    EXPECT_EQ(s.volume().emission[0].color, glm::vec3(1.0f));
    EXPECT_EQ(s.volume().emission[0].intensity, 1.0f);
    const EmissionSource& b = s.volume().emission[1];
    EXPECT_EQ(b.grid, (GridRef{"temperature", 1}));
    EXPECT_EQ(b.kind, EmissionKind::Blackbody);
    EXPECT_EQ(b.normalization, BlackbodyNormalization::Physical);
    EXPECT_EQ(b.temperature_scale, 1000.0f);
    EXPECT_EQ(b.temperature_offset, -100.0f);
    EXPECT_EQ(b.cutoff, 900.0f);
    EXPECT_EQ(b.reference_temperature, 1800.0f);
    EXPECT_EQ(s.volume().emission[2].normalization, BlackbodyNormalization::Luminance);
    EXPECT_EQ(s.volume().emission[2].temperature_scale, 1.0f);
    ASSERT_EQ(s.volume().emission[3].ramp.size(), 2u);
    EXPECT_EQ(s.volume().emission[3].ramp[1].color, glm::vec3(4, 2, 1));
    // A luminance-normalised blackbody writes no reference temperature: it has none.
    const nlohmann::json expected = nlohmann::json::parse(R"([
        {"grid": "flame", "intensity": 1, "kind": "constant", "color": [1, 1, 1]},
        {"grid": {"name": "temperature", "index": 1}, "intensity": 2, "kind": "blackbody", "temperature_scale": 1000,
         "temperature_offset": -100, "cutoff": 900, "normalization": "physical", "reference_temperature": 1800},
        {"grid": "heat", "intensity": 1, "kind": "blackbody", "temperature_scale": 1, "temperature_offset": 0, "cutoff": 0,
         "normalization": "luminance"},
        {"grid": "flame", "intensity": 1, "kind": "ramp",
         "ramp": [{"value": 0, "color": [0, 0, 0]}, {"value": 2, "color": [4, 2, 1]}]}])");
    EXPECT_EQ(sceneToJson(s)["volumes"][0]["emission"], expected) << sceneToJson(s)["volumes"][0]["emission"].dump(2);
    const Scene again = parseScene(sceneToJson(s).dump(), "again.json", "");
    EXPECT_EQ(sceneToJson(again)["volumes"][0]["emission"], expected);
}

// Keys of another kind, bad values, too many sources: one line naming the key.
TEST(EmissionScene, ErrorsNameTheKey) {
    const std::string v = R"({"volume": {"path": "a.vdb"}, "emission": )";
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "kind": "plasma"}]})"),
              "shot.json: /emission/0/kind: 'plasma' is not one of constant, blackbody, ramp");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t"}, {"grid": "t", "kind": "blackbody", "color": [1, 0, 0]}]})"),
              "shot.json: /emission/1/color: unknown key (expected one of grid, kind, intensity, temperature_scale, "
              "temperature_offset, cutoff, normalization)");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "kind": "blackbody", "reference_temperature": 1000}]})"),
              "shot.json: /emission/0/reference_temperature: unknown key (expected one of grid, kind, intensity, "
              "temperature_scale, temperature_offset, cutoff, normalization)");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "temperature_scale": 2}]})"),
              "shot.json: /emission/0/temperature_scale: unknown key (expected one of grid, kind, intensity, color)");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "f", "kind": "ramp", "ramp": [{"value": 0, "color": [0, 0, 0]},
                                                                   {"value": 2, "color": [1, 1, 1]},
                                                                   {"value": 1, "color": [1, 0, 0]}]}]})"),
              "shot.json: /emission/0/ramp/2/value: ramp points must have increasing values");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "f", "kind": "ramp", "ramp": [{"value": 0, "color": [0, 0, 0]}]}]})"),
              "shot.json: /emission/0/ramp: needs at least 2 points");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "f", "kind": "ramp", "ramp": [{"value": 0.2, "color": [1, 0, 0]},
                                                                   {"value": 1, "color": [1, 1, 0]}]}]})"),
              "shot.json: /emission/0/ramp: must be black at value 0 (empty space emits nothing)");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "kind": "blackbody", "temperature_offset": 300}]})"),
              "shot.json: /emission/0/temperature_offset: value 0 (empty space) would emit at 300 K: keep the offset "
              "below cutoff");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "intensity": -1}]})"),
              "shot.json: /emission/0/intensity: must be a finite number >= 0");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "color": [1, -0.5, 0]}]})"),
              "shot.json: /emission/0/color: must be finite and >= 0");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "kind": "blackbody", "temperature_scale": 0}]})"),
              "shot.json: /emission/0/temperature_scale: must be a finite number > 0");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "t", "kind": "blackbody", "normalization": "physical", "reference_temperature": 0}]})"),
              "shot.json: /emission/0/reference_temperature: must be a finite temperature > 0 K");
    EXPECT_EQ(sceneErrorOf(v + R"([{"kind": "constant"}]})"), "shot.json: /emission/0/grid: required key is missing");
    EXPECT_EQ(sceneErrorOf(v + R"([{"grid": "a"}, {"grid": "b"}, {"grid": "c"}, {"grid": "d"}, {"grid": "e"}]})"),
              "shot.json: /emission: at most 4 sources (got 5)");
    // The old single-grid keys are gone.
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb", "emission": "heat"}})"),
              "shot.json: /volume/emission: unknown key (expected one of name, path, frames, density, color, level_set, up, transform, instances, role, enabled)");
}

}  // namespace
}  // namespace voxlux::test
