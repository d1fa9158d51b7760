// `volumes`: a list of named volumes, each with its own material and emission; `volume` with
// `material` and `emission` beside it is a list of one. Names come from the file when unset and
// are unique; the written scene is the list; `--set` reaches a volume by index or name, and the
// one volume's keys by their `volume` spelling.
#include "core/error.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

TEST(SceneVolumes, AnEntryHoldsItsNameCacheMaterialAndEmission) {
    const Scene s = parseScene(R"({"volumes": [{"name": "plume", "path": "smoke.####.vdb", "frames": [1, 2],
        "transform": {"translate": [1, 0, 0]}, "material": {"albedo": [0.5, 0.6, 0.7], "anisotropy": 0.4},
        "emission": [{"grid": "heat", "kind": "constant", "color": [1, 0.5, 0]}]}]})", "shot.json", "/shots");
    ASSERT_EQ(s.volumes.size(), 1u);
    const VolumeSpec& v = s.volume();
    EXPECT_EQ(v.name, "plume");
    EXPECT_EQ(v.path, "/shots/smoke.####.vdb");
    EXPECT_EQ(v.transform->translate, glm::vec3(1, 0, 0));
    EXPECT_EQ(v.material.albedo, glm::vec3(0.5f, 0.6f, 0.7f));
    EXPECT_EQ(v.material.anisotropy, 0.4f);
    ASSERT_EQ(v.emission.size(), 1u);
    EXPECT_EQ(v.emission[0].grid.name, "heat");
    EXPECT_EQ(sceneToJson(parseScene(sceneToJson(s).dump(), "again.json", "")), sceneToJson(s));
}

TEST(SceneVolumes, TheOneVolumeFormIsAListOfOne) {
    const Scene one = parseScene(R"({"volume": {"path": "fire.####.vdb", "frames": [1, 2]}, "material": {"density_scale": 3},
        "emission": [{"grid": "temperature", "kind": "blackbody"}]})", "shot.json", "");
    const Scene list = parseScene(R"({"volumes": [{"name": "fire", "path": "fire.####.vdb", "frames": [1, 2],
        "material": {"density_scale": 3}, "emission": [{"grid": "temperature", "kind": "blackbody"}]}]})", "shot.json", "");
    EXPECT_EQ(sceneToJson(one), sceneToJson(list));
    EXPECT_FALSE(sceneToJson(one).contains("volume"));
    EXPECT_FALSE(sceneToJson(one).contains("material"));
}

TEST(SceneVolumes, NamesComeFromTheFileAndHoldOnlyWhatAChannelNameMay) {
    const auto nameOf = [](const std::string& path) {
        return parseScene(R"({"volume": {"path": ")" + path + R"("}})", "shot.json", "").volume().name;
    };
    EXPECT_EQ(nameOf("caches/fire.####.vdb"), "fire");
    EXPECT_EQ(nameOf("fluid_data_####.vdb"), "fluid_data");
    EXPECT_EQ(nameOf("my cloud (v2).vdb"), "my_cloud__v2");
    EXPECT_EQ(nameOf("####.vdb"), "volume");
    const std::string entry = R"({"volumes": [{"path": "a.vdb", "name": )";
    EXPECT_EQ(sceneErrorOf(entry + R"("fire.main"}]})"), "shot.json: /volumes/0/name: 'fire.main' must be letters, digits, '_' and '-'");
    EXPECT_EQ(sceneErrorOf(entry + R"(""}]})"), "shot.json: /volumes/0/name: '' must be letters, digits, '_' and '-'");
}

TEST(SceneVolumes, ConflictsAndDuplicatesAreRefused) {
    EXPECT_EQ(sceneErrorOf(R"({"volume": {"path": "a.vdb"}, "volumes": [{"path": "b.vdb"}]})"),
              "shot.json: /volume: goes alone, with material and emission beside it, or as an entry of volumes: not both");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "b.vdb"}], "material": {"density_scale": 2}})"),
              "shot.json: /material: goes in each entry of volumes");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": []})"), "shot.json: /volumes: expected at least one volume");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "shadow": "matte"}]})"),
              "shot.json: /volumes/0/shadow: unknown key (expected one of name, path, frames, density, color, level_set, up, transform, instances, role, enabled, material, emission)");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a/smoke.vdb"}, {"path": "b/smoke.vdb"}]})"),
              "shot.json: /volumes/1/name: 'smoke' is also volume 0's name (taken from the file's; set name)");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "name": "x"}, {"path": "b.vdb", "name": "x"}]})"),
              "shot.json: /volumes/1/name: 'x' is also volume 0's name");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "color": "Cd", "material": {"transfer_function_2d": "ct_tissue"}}]})"),
              "shot.json: /volumes/0/color: the 2D transfer function (material.transfer_function_2d) gives the albedo; remove color");
}

// A disabled volume stays in the scene (written back, `enabled: false`) and is left out of the
// render; what it holds is not refused, as it does not render; one volume stays enabled.
TEST(SceneVolumes, ADisabledVolumeIsKeptAndLeftOutOfTheRender) {
    const Scene s = parseScene(R"({"volumes": [{"path": "a.vdb"}, {"path": "b.vdb", "enabled": false,
        "material": {"transfer_function_2d": "ct_tissue"}}]})", "shot.json", "");
    ASSERT_EQ(s.volumes.size(), 2u);
    EXPECT_FALSE(s.volumes[1].enabled);
    EXPECT_EQ(sceneToJson(s)["volumes"][1]["enabled"], false);
    EXPECT_FALSE(sceneToJson(s)["volumes"][0].contains("enabled"));
    const Scene rendered = withEnabledVolumes(s);
    ASSERT_EQ(rendered.volumes.size(), 1u);
    EXPECT_EQ(rendered.volume().name, "a");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb", "enabled": false}]})"),
              "shot.json: /volumes: every volume is disabled (enabled: false): a scene renders one at least");
    EXPECT_EQ(sceneErrorOf(R"({"volumes": [{"path": "a.vdb"}, {"path": "b.vdb", "material": {"transfer_function_2d": "ct_tissue"}}]})"),
              "shot.json: /volumes/1/material/transfer_function_2d: set: a volume of several takes a 1D transfer function "
              "(transfer_function) only, so far");
}

TEST(SceneVolumes, SetReachesAVolumeByIndexOrNameAndTheOneVolumesKeysAsWritten) {
    nlohmann::json j = sceneToJson(parseScene(R"({"volume": {"path": "smoke.vdb"}, "lights": [{"name": "key", "direction": [0, -1, 0]}]})", "shot.json", ""));
    applySceneSet(j, "material.albedo=[0.1,0.2,0.3]");
    applySceneSet(j, "volume.up=z");
    applySceneSet(j, "volumes.smoke.material.anisotropy=0.5");
    applySceneSet(j, "volumes.0.level_set=fog");
    applySceneSet(j, "lights.key.intensity=3");
    const Scene s = sceneFromJson(j, "set", "");
    EXPECT_EQ(s.volume().material.albedo, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(s.volume().up, UpAxis::Z);
    EXPECT_EQ(s.volume().material.anisotropy, 0.5f);
    EXPECT_EQ(s.volume().level_set, LevelSetPolicy::ConvertToFog);
    EXPECT_EQ(s.lights[0].intensity, 3.0f);
    EXPECT_EQ(inputErrorOf([&] { applySceneSet(j, "volumes.fire.material.anisotropy=0.5"); }),
              "--set 'volumes.fire.material.anisotropy=0.5': no element 'fire' (an index below 1 or a name)");
    j["volumes"].push_back(j["volumes"][0]);
    EXPECT_EQ(inputErrorOf([&] { applySceneSet(j, "material.albedo=0.5"); }),
              "--set 'material.albedo=0.5': the scene has 2 volumes; name one, as volumes.<name>.material.");
}

}  // namespace
}  // namespace voxlux::test
