// Extinction-SAT's settings (extinction_sat_settings.h): the effects keys it owns reach the scene
// through the generated MethodSettings, writeSettings writes exactly them and reads back, and bad
// values are named by their key.
#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/json_reader.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

TEST(ExtinctionSatSettings, ReadBackWhatTheyWrite) {
    ExtinctionSatSettings s;
    s.ambient_occlusion = AmbientOcclusion{5, 0.25f};
    s.color_bleeding = 0.4f;
    s.cone = ShadowCone{7.5f, 33, 0.1f};
    nlohmann::json effects = nlohmann::json::object();
    writeSettings(s, effects);
    EXPECT_EQ(effects, nlohmann::json::parse(R"({"ambient_occlusion": {"shells": 5, "radius": 0.25},
        "color_bleeding": 0.4, "cone": {"angle": 7.5, "samples": 33, "growth": 0.1}})"));
    EXPECT_EQ(effects.size(), ExtinctionSatSettings::keys().size());   // exactly its keys
    for (const std::string& key : ExtinctionSatSettings::keys()) EXPECT_TRUE(effects.contains(key)) << key;
    ExtinctionSatSettings back;
    readSettings(JsonObject(effects, "shot.json", "/effects"), back);
    ASSERT_TRUE(back.ambient_occlusion);
    EXPECT_EQ(back.ambient_occlusion->shells, 5);
    EXPECT_EQ(back.ambient_occlusion->radius, 0.25f);
    EXPECT_EQ(back.color_bleeding, 0.4f);
    EXPECT_EQ(back.cone.angle, 7.5f);
    EXPECT_EQ(back.cone.samples, 33);
    EXPECT_EQ(back.cone.growth, 0.1f);
}

TEST(ExtinctionSatSettings, AreTheScenesEffectsKeysAndShadowValue) {
    const Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "effects": {"shadows": "sat_cone",
        "ambient_occlusion": true, "color_bleeding": true, "cone": {"samples": 12}}})", "shot.json", "/shots");
    EXPECT_EQ(s.effects.shadows, ShadowMethod::SatCone);
    EXPECT_EQ(shadowMethodName(ShadowMethod::SatCone), "sat_cone");
    ASSERT_TRUE(s.effects.ambient_occlusion);
    EXPECT_EQ(s.effects.ambient_occlusion->shells, 3);
    EXPECT_EQ(s.effects.color_bleeding, 1.0f);
    EXPECT_EQ(s.effects.cone.samples, 12);
    const std::vector<std::string> keys = methodSettingKeys();
    for (const std::string& key : ExtinctionSatSettings::keys()) EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
}

TEST(ExtinctionSatSettings, BadValuesNameTheirKey) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"cone": {"angle": 60}}})"),
              "shot.json: /effects/cone/angle: must lie in [0, 60) degrees");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"cone": {"samples": 0}}})"),
              "shot.json: /effects/cone/samples: must lie in 1..1024");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"ambient_occlusion": {"shells": 3, "radios": 2}}})"),
              "shot.json: /effects/ambient_occlusion/radios: unknown key (expected one of shells, radius)");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"ambient_occlusion": 3}})"),
              "shot.json: /effects/ambient_occlusion: expected true, false or an object");
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "effects": {"color_bleeding": 2}})"),
              "shot.json: /effects/color_bleeding: must be true, false or a strength in [0, 1]");
}

}  // namespace
}  // namespace voxlux::test
