// `voxlux calibrate` (src/tools/calibrate.h): it recovers the indirect settings a synthetic truth
// was rendered with, writes a scene that renders that truth, and refuses a scene or a truth it
// cannot fit.
#include <fstream>

#include <nlohmann/json.hpp>

#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// The noisy ball under a sun and a sky, propagation with Kniss's indirect light of `transport`
// and `strength`, written float so the truth is not rounded.
nlohmann::json knissBall(const std::string& vdb, float transport, float strength) {
    return {{"volume", {{"path", vdb}}},
            {"material", {{"density_scale", 8}, {"albedo", {0.9, 0.9, 0.9}}, {"anisotropy", 0.3}}},
            {"lights", {{{"type", "directional"}, {"direction", {-1, -1, -0.5}}, {"intensity", 4}},
                        {{"type", "ambient"}, {"intensity", 0.5}}}},
            {"render", {{"resolution", {48, 40}}, {"backend", "cpu"}}},
            {"effects", {{"shadows", "propagation"}, {"light_resolution", 32},
                         {"indirect", {{"transport_color", {transport, transport, transport}}, {"strength", strength}}}}},
            {"output", {{"path", "truth.exr"}, {"pixel_type", "float"}}}};
}

void writeJson(const std::string& path, const nlohmann::json& j) { std::ofstream(path) << j.dump(2); }

TEST(Calibrate, RecoversTheSettingsASyntheticTruthWasRenderedWith) {
    const std::string dir = tempDir("calibrate");
    const std::string vdb = writeBall(dir);
    writeJson(dir + "/truth.json", knissBall(vdb, 0.45f, 0.7f));
    ASSERT_EQ(runCli("render " + dir + "/truth.json -o " + dir + "/truth.exr").exit_code, 0);
    // Start from other settings: the diffusion model at strength 1.
    nlohmann::json start = knissBall(vdb, 0.45f, 0.7f);
    start["effects"]["indirect"] = {{"strength", 1.0}};
    writeJson(dir + "/start.json", start);
    const CliResult r = runCli("calibrate " + dir + "/start.json --truth " + dir + "/truth.exr -o " + dir + "/fitted.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::printf("%s", r.out.c_str());
    const nlohmann::json fitted = nlohmann::json::parse(std::ifstream(dir + "/fitted.json"));
    const nlohmann::json& in = fitted["effects"]["indirect"];
    EXPECT_EQ(in["model"], "kniss");
    EXPECT_NEAR(in["transport_color"][0].get<double>(), 0.45, 0.005);
    EXPECT_NEAR(in["strength"].get<double>(), 0.7, 0.01);
    // The fitted scene renders the truth again (to the golden section's last step).
    ASSERT_EQ(runCli("render " + dir + "/fitted.json -o " + dir + "/again.exr").exit_code, 0);
    const Exr truth = readExr(dir + "/truth.exr"), again = readExr(dir + "/again.exr");
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < truth.planes.at("R").size(); ++i) {
        worst = std::max(worst, double(std::abs(truth.planes.at("R")[i] - again.planes.at("R")[i])));
        peak = std::max(peak, double(truth.planes.at("R")[i]));
    }
    EXPECT_LT(worst, 0.01 * peak);
    EXPECT_NE(r.out.find("calibrated at 48x40: RMSE "), std::string::npos) << r.out;
}

TEST(Calibrate, RefusesASceneWithoutPropagatedIndirectLight) {
    const std::string dir = tempDir("calibrate_refuses");
    nlohmann::json j = knissBall(writeBall(dir), 0.5f, 1.0f);
    j["effects"] = {{"shadows", "raymarch"}};
    writeJson(dir + "/raymarch.json", j);
    const CliResult r = runCli("calibrate " + dir + "/raymarch.json -o " + dir + "/out.json");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: calibrate: fits effects.indirect, which needs render.method \"march\", "
                     "effects.shadows \"propagation\" and effects.indirect (--quality preview sets all three)\n");
    EXPECT_FALSE(std::ifstream(dir + "/out.json").good());

    // A given truth of another framing, or a black one, is refused, and nothing is written.
    const std::string vdb = dir + "/ball.vdb";
    writeJson(dir + "/ball.json", knissBall(vdb, 0.5f, 1.0f));
    ASSERT_EQ(runCli("render " + dir + "/ball.json --res 48x20 -o " + dir + "/wide.exr").exit_code, 0);
    const CliResult wide = runCli("calibrate " + dir + "/ball.json --truth " + dir + "/wide.exr -o " + dir + "/out.json");
    EXPECT_EQ(wide.exit_code, 2);
    EXPECT_EQ(wide.err, "voxlux: error: " + dir + "/wide.exr: 48x20 does not have the scene's aspect (48x40)\n");
    nlohmann::json dark = knissBall(vdb, 0.5f, 1.0f);
    for (auto& light : dark["lights"]) light["intensity"] = 0;
    writeJson(dir + "/dark.json", dark);
    ASSERT_EQ(runCli("render " + dir + "/dark.json -o " + dir + "/black.exr").exit_code, 0);
    const CliResult black = runCli("calibrate " + dir + "/ball.json --truth " + dir + "/black.exr -o " + dir + "/out.json");
    EXPECT_EQ(black.exit_code, 2);
    EXPECT_EQ(black.err, "voxlux: error: " + dir + "/black.exr: the image is black (or has no R, G, B channels): nothing to fit\n");
    EXPECT_FALSE(std::ifstream(dir + "/out.json").good());
}

}  // namespace
}  // namespace voxlux::test
