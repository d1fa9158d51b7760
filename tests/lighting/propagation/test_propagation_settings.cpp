// Illumination propagation's settings (propagation_settings.h): the effects keys it owns reach the
// scene through the generated MethodSettings, writeSettings writes exactly them and reads back, and
// bad values are named by their key.
#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/json_reader.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

TEST(PropagationSettings, ReadBackWhatTheyWrite) {
    PropagationSettings s;
    s.propagation = Propagation{true, true, true, false, Filter::Trilinear};
    s.indirect = Indirect{IndirectModel::Kniss, 0.5f, 20.0f, 5, BlurPhase::HenyeyGreenstein, 2.0f, 0.3f, glm::vec3(0.5f, 0.6f, 0.7f)};
    nlohmann::json effects = nlohmann::json::object();
    writeSettings(s, effects);
    EXPECT_EQ(effects, nlohmann::json::parse(R"({
        "propagation": {"blend_axes": true, "eye_pass": true, "chroma_subsampling": true, "coherent": false, "filter": "trilinear"},
        "indirect": {"model": "kniss", "strength": 0.5, "angle": 20, "samples": 5, "phase": "henyey_greenstein",
                     "exponent": 2, "g": 0.3, "transport_color": [0.5, 0.6, 0.7]}})"));
    EXPECT_EQ(effects.size(), PropagationSettings::keys().size());   // exactly its keys
    for (const std::string& key : PropagationSettings::keys()) EXPECT_TRUE(effects.contains(key)) << key;
    PropagationSettings back;
    readSettings(JsonObject(effects, "shot.json", "/effects"), back);
    nlohmann::json again = nlohmann::json::object();
    writeSettings(back, again);
    EXPECT_EQ(again, effects);
}

TEST(PropagationSettings, AreTheScenesEffectsKeysAndShadowValue) {
    const Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "effects": {"shadows": "propagation",
        "indirect": true, "propagation": {"eye_pass": true}}})", "shot.json", "/shots");
    EXPECT_EQ(s.effects.shadows, ShadowMethod::Propagation);
    EXPECT_EQ(shadowMethodName(ShadowMethod::Propagation), "propagation");
    ASSERT_TRUE(s.effects.indirect);
    EXPECT_EQ(s.effects.indirect->model, IndirectModel::Diffusion);
    EXPECT_TRUE(s.effects.propagation.eye_pass);
    EXPECT_EQ(s.effects.propagation.filter, Filter::Tricubic);
    const std::vector<std::string> keys = methodSettingKeys();
    for (const std::string& key : PropagationSettings::keys()) EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
}

TEST(PropagationSettings, BadValuesNameTheirKey) {
    const std::string v = R"({"volume": {"path": "a.vdb"}, "effects": )";
    EXPECT_EQ(sceneErrorOf(v + R"({"indirect": {"transport_color": [1, 0, 0.5]}}})"),
              "shot.json: /effects/indirect/transport_color: each component must lie in (0, 1]");
    EXPECT_EQ(sceneErrorOf(v + R"({"indirect": {"model": "diffusion", "transport_color": [1, 0.5, 0.5]}}})"),
              "shot.json: /effects/indirect/transport_color: is the kniss model's; the diffusion model derives it from "
              "material.albedo and anisotropy");
    EXPECT_EQ(sceneErrorOf(v + R"({"indirect": {"model": "dipole"}}})"),
              "shot.json: /effects/indirect/model: 'dipole' is not one of diffusion, kniss");
    EXPECT_EQ(sceneErrorOf(v + R"({"indirect": {"samples": 33}}})"),
              "shot.json: /effects/indirect/samples: must lie in 1..32");
    EXPECT_EQ(sceneErrorOf(v + R"({"indirect": {"phase": "mie"}}})"),
              "shot.json: /effects/indirect/phase: 'mie' is not one of phong, henyey_greenstein");
    EXPECT_EQ(sceneErrorOf(v + R"({"indirect": 3}})"), "shot.json: /effects/indirect: expected true, false or an object");
    EXPECT_EQ(sceneErrorOf(v + R"({"propagation": {"eye": true}}})"),
              "shot.json: /effects/propagation/eye: unknown key (expected one of blend_axes, eye_pass, chroma_subsampling, coherent, filter)");
    EXPECT_EQ(sceneErrorOf(v + R"({"propagation": {"filter": "cubic"}}})"),
              "shot.json: /effects/propagation/filter: 'cubic' is not one of trilinear, tricubic");
}

}  // namespace
}  // namespace voxlux::test
