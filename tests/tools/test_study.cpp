// `voxlux study`: the error measures, the CSV it resumes from, the Pareto front, the reference's
// fitted curve and crossover (hand-computed cases), the plan of configs, and a whole small study.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "tools/image_metrics.h"
#include "render/renderer.h"
#include "render/write_stage.h"
#include "scene/scene_json.h"
#include "tools/study.h"
#include "tools/study_plan.h"
#include "tools/study_report.h"
#include "tools/study_results.h"
#include "tools/svg_plot.h"
#include "core/error.h"
#include "test_support.h"

namespace voxlux {
namespace {

RenderImage uniformImage(glm::vec3 rgb, int w = 4, int h = 3) {
    RenderImage im;
    im.width = w;
    im.height = h;
    im.pixels.resize(size_t(w) * h);
    for (auto& p : im.pixels) p.rgba = glm::vec4(rgb, 1.0f);
    return im;
}

// SMPTE ST 2084 inverse EOTF, written out from the standard's constants.
double pqOf(double nits) {
    const double y = nits / 10000.0, m1 = 0.1593017578125, m2 = 78.84375;
    const double c1 = 0.8359375, c2 = 18.8515625, c3 = 18.6875;
    return std::pow((c1 + c2 * std::pow(y, m1)) / (1 + c3 * std::pow(y, m1)), m2);
}

// Rec.2020 -> XYZ (BT.2020 primaries, D65): greys in this "working space" are Rec.2020 greys.
const glm::mat3 kRec2020ToXyz = glm::transpose(glm::mat3(0.6369580f, 0.1446169f, 0.1688810f,  //
                                                         0.2627002f, 0.6779981f, 0.0593017f,  //
                                                         0.0f, 0.0280727f, 1.0609851f));

TEST(ImageMetrics, MeanSquaredErrorOverRgb) {
    const RenderImage a = uniformImage({0.5f, 0.5f, 0.5f}), b = uniformImage({0.5f, 0.8f, 0.1f});
    EXPECT_NEAR(meanSquaredError(a, b), (0.09 + 0.16) / 3.0, 1e-7);
    EXPECT_EQ(meanSquaredError(a, a), 0.0);
    EXPECT_NEAR(halvesNoiseMse(a, b), (0.09 + 0.16) / 12.0, 1e-7);
    EXPECT_THROW(meanSquaredError(a, uniformImage({0, 0, 0}, 3, 3)), std::invalid_argument);
}

TEST(ImageMetrics, DeltaEItpOfGreysIs720TimesTheirPqDifference) {
    // A grey has L = M = S, so I = PQ(Y) and T = P = 0 (BT.2124): Delta E = 720 |PQ(Y1) - PQ(Y2)|.
    for (double white : {100.0, 1000.0}) {
        const RenderImage a = uniformImage({1.0f, 1.0f, 1.0f}), b = uniformImage({1.1f, 1.1f, 1.1f});
        const double expected = 720.0 * (pqOf(1.1 * white) - pqOf(white));
        const double got = meanDeltaEItp(a, b, kRec2020ToXyz, white);
        std::printf("  grey 1.0 vs 1.1 at %.0f nits: Delta E ITP %.4f (expected %.4f)\n", white, got, expected);
        EXPECT_NEAR(got, expected, 1e-3 * expected);
    }
    const RenderImage a = uniformImage({0.4f, 0.2f, 0.1f});
    EXPECT_EQ(meanDeltaEItp(a, a, kRec2020ToXyz), 0.0);
    // A hue change of equal luminance still counts; the measure is symmetric.
    const RenderImage b = uniformImage({0.3f, 0.25f, 0.1f});
    EXPECT_GT(meanDeltaEItp(a, b, kRec2020ToXyz), 1.0);
    EXPECT_DOUBLE_EQ(meanDeltaEItp(a, b, kRec2020ToXyz), meanDeltaEItp(b, a, kRec2020ToXyz));
}

StudyRow row(const std::string& id, const std::string& method, int spp, double seconds, double rmse, double delta_e = 1) {
    return StudyRow{id, method, spp, seconds, rmse, delta_e};
}

TEST(StudyResults, CsvRoundTripsQuotesAndDropsALineCutShort) {
    const std::string dir = test::tempDir("study_csv");
    const std::string path = dir + "/study.csv";
    StudyRow a = row(R"(effects.indirect={"samples":3,"angle":20} render.step=0.5)", "propagation+indirect", 0, 1.25, 0.0123, 2.5);
    a.front_rmse = true;
    const StudyRow b = row("render.method=reference render.reference.spp=4", "reference", 4, 2.0, 0.05, 3.0);
    std::ofstream(path) << studyCsvHeader("scene abc") << studyCsvRow(a) << studyCsvRow(b) << "\"render.method=ma";
    const auto rows = readStudyCsv(path, "scene abc");
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].id, a.id);
    EXPECT_EQ(rows[0].method, a.method);
    EXPECT_DOUBLE_EQ(rows[0].seconds, 1.25);
    EXPECT_DOUBLE_EQ(rows[0].rmse, 0.0123);
    EXPECT_TRUE(rows[0].front_rmse);
    EXPECT_FALSE(rows[0].front_delta_e);
    EXPECT_EQ(rows[1].spp, 4);
    // Measured against another scene or truth: nothing is kept.
    EXPECT_TRUE(readStudyCsv(path, "scene xyz").empty());
    EXPECT_TRUE(readStudyCsv(dir + "/absent.csv", "scene abc").empty());
}

TEST(StudyResults, ParetoFrontKeepsOnlyUndominatedRows) {
    std::vector<StudyRow> rows = {row("a", "m", 0, 1.0, 0.5, 9), row("b", "m", 0, 2.0, 0.3, 1), row("c", "m", 0, 3.0, 0.4, 0.5),
                                  row("d", "m", 0, 0.5, 0.9, 9)};
    markParetoFronts(rows);
    EXPECT_TRUE(rows[0].front_rmse);
    EXPECT_TRUE(rows[1].front_rmse);
    EXPECT_FALSE(rows[2].front_rmse);   // b is faster and more accurate
    EXPECT_TRUE(rows[3].front_rmse);
    // By Delta E: a ties d's error but is slower; b and c each buy accuracy with time.
    EXPECT_FALSE(rows[0].front_delta_e);
    EXPECT_TRUE(rows[1].front_delta_e);
    EXPECT_TRUE(rows[2].front_delta_e);
    EXPECT_TRUE(rows[3].front_delta_e);
}

TEST(StudyResults, ReferenceCurveAndCrossoverByHand) {
    // seconds = 0.2 + 0.05 spp, RMSE = 0.8 / sqrt(spp), exactly.
    std::vector<StudyRow> rows;
    for (int spp : {1, 4, 16, 64})
        rows.push_back(row("ref" + std::to_string(spp), "reference", spp, 0.2 + 0.05 * spp, 0.8 / std::sqrt(double(spp))));
    const auto curve = fitReferenceCurve(rows);
    ASSERT_TRUE(curve);
    EXPECT_NEAR(curve->t0, 0.2, 1e-9);
    EXPECT_NEAR(curve->k, 0.05, 1e-9);
    EXPECT_NEAR(curve->sigma, 0.8, 1e-9);
    EXPECT_NEAR(curve->secondsFor(0.2), 1.0, 1e-9);
    EXPECT_NEAR(curve->secondsFor(1.6), 0.25, 1e-9);   // a quarter sample's error: one sample's time, never less
    // A fit with a negative offset (the MRI head's): one sample costs its slope, not t0 + k.
    const ReferenceCurve negative{-0.536, 0.7988, 0.1239};
    EXPECT_NEAR(negative.secondsFor(0.2249), 0.7988, 1e-9);
    EXPECT_NEAR(negative.secondsFor(0.1239 / 4.0), -0.536 + 0.7988 * 16.0, 1e-9);
    EXPECT_NEAR(curve->rmseAt(1.0), 0.2, 1e-9);
    EXPECT_TRUE(std::isinf(curve->rmseAt(0.21)));   // not even one sample

    // p1 at 0.1 s with 0.4 (the reference needs 0.4 s), p2 at 0.5 s with 0.2 (it needs 1.0 s),
    // p3 slower and worse than p2 (off the front): the approximations win until 1.0 s; the least
    // speed-up is p2's 2x.
    rows.push_back(row("p1", "sat_cone", 0, 0.1, 0.4));
    rows.push_back(row("p2", "sat_cone", 0, 0.5, 0.2));
    rows.push_back(row("p3", "raymarch", 0, 0.9, 0.3));
    const Crossover c = crossoverOf(rows, *curve);
    EXPECT_NEAR(c.seconds, 1.0, 1e-9);
    EXPECT_NEAR(c.min_speedup, 2.0, 1e-9);
    EXPECT_EQ(c.min_speedup_id, "p2");

    const auto floors = biasFloors(rows);
    ASSERT_EQ(floors.size(), 2u);
    EXPECT_EQ(floors[0].method, "sat_cone");
    EXPECT_DOUBLE_EQ(floors[0].rmse, 0.2);
    EXPECT_EQ(floors[1].method, "raymarch");

    // An approximation that the reference beats even at its own time: no crossover.
    const Crossover none = crossoverOf({rows[0], rows[1], rows[2], rows[3], row("slow", "m", 0, 5.0, 0.3)}, *curve);
    EXPECT_EQ(none.seconds, 0.0);
    EXPECT_NEAR(none.min_speedup, (0.2 + 0.05 * (0.8 / 0.3) * (0.8 / 0.3)) / 5.0, 1e-9);
}

nlohmann::json ballScene(const std::string& vdb, bool ambient) {
    nlohmann::json j = {{"volume", {{"path", vdb}}},
                        {"material", {{"density_scale", 8}, {"albedo", {0.9, 0.9, 0.9}}}},
                        {"lights", {{{"type", "directional"}, {"direction", {-1, -1, -0.5}}, {"intensity", 4}}}},
                        {"render", {{"resolution", {24, 20}}}},
                        {"output", {{"path", "unused.exr"}}}};
    if (ambient) j["lights"].push_back({{"type", "ambient"}, {"intensity", 0.5}});
    return j;
}

TEST(StudyPlan, EveryMethodOnceAndAOOnlyWithAnAmbientLight) {
    const std::string vdb = test::writeBall(test::tempDir("study_plan"));
    for (bool ambient : {false, true}) {
        const nlohmann::json base = sceneToJson(parseScene(ballScene(vdb, ambient).dump(), "s.json", ""));
        const StudyPlan plan = planStudy(base, {1, 4, 16}, 7);
        std::set<std::string> methods, hashes, ids;
        std::vector<int> spps;
        for (const auto& c : plan.configs) {
            methods.insert(c.method);
            ids.insert(c.id());
            hashes.insert(sceneHash(studyScene(base, c)));
            if (c.spp) spps.push_back(c.spp);
        }
        EXPECT_EQ(hashes.size(), plan.configs.size()) << "two configs render the same scene";
        EXPECT_EQ(ids.size(), plan.configs.size());
        EXPECT_EQ(spps, (std::vector<int>{1, 4, 16, 256}));   // 256: the final preset
        for (const char* m : {"unshadowed", "raymarch", "sat_cone", "propagation", "propagation+indirect", "reference"})
            EXPECT_TRUE(methods.count(m)) << m;
        EXPECT_EQ(methods.count("sat_cone+AO"), ambient ? 1u : 0u);
        EXPECT_EQ(methods.count("propagation+indirect+AO"), ambient ? 1u : 0u);
        // The sat_cone defaults are one render shared by its three sweeps.
        std::set<size_t> defaults;
        for (const auto& s : plan.sweeps)
            if (s.method == "sat_cone")
                for (size_t i = 0; i < s.labels.size(); ++i)
                    if (s.labels[i] == "128" || s.labels[i] == "20" || s.labels[i] == "2") defaults.insert(s.configs[i]);
        EXPECT_EQ(defaults.size(), 1u);
        // The presets: preview is the propagation+indirect defaults, measured once.
        const StudySweep& presets = plan.sweeps.back();
        ASSERT_EQ(presets.method, kPresetSweep);
        EXPECT_EQ(presets.labels, (std::vector<std::string>{"draft", "preview", "final"}));
        const StudyConfig& draft = plan.configs[presets.configs[0]];
        EXPECT_EQ(draft.method, "propagation+indirect");
        EXPECT_EQ(studyScene(base, draft).effects.light_resolution, 64);
        size_t indirect_defaults = 0;
        for (const auto& s : plan.sweeps)
            if (s.method == "propagation+indirect" && s.knob == "effects.light_resolution") indirect_defaults = s.configs[1];
        EXPECT_EQ(presets.configs[1], indirect_defaults);
        const Scene final_ = studyScene(base, plan.configs[presets.configs[2]]);
        EXPECT_EQ(final_.render.method, RenderMethod::Reference);
        EXPECT_EQ(final_.render.reference.spp, 256);
        EXPECT_EQ(final_.render.reference.seed, 1);   // the scene's own, as --quality final renders it
    }
}

// A scene of several volumes studies what it can render and says what it refuses: the diffusion
// model of indirect light, as the volumes' materials differ (Kniss's model takes any).
TEST(StudyPlan, SeveralVolumesStudyEveryMethodTheyTake) {
    const std::string vdb = test::writeBall(test::tempDir("study_plan_several"));
    nlohmann::json j = ballScene(vdb, true);
    j["volumes"] = {{{"path", vdb}, {"name", "a"}, {"material", j["material"]}},
                    {{"path", vdb}, {"name", "b"}, {"transform", {{"translate", {1, 0, 0}}}}, {"material", {{"albedo", {0.5, 0.5, 0.5}}}}}};
    j.erase("volume");
    j.erase("material");
    const nlohmann::json base = sceneToJson(parseScene(j.dump(), "s.json", ""));
    const StudyPlan plan = planStudy(base, {1}, 1);
    std::set<std::string> methods;
    for (const auto& s : plan.sweeps) methods.insert(s.method);
    for (const char* m : {"unshadowed", "raymarch", "sat_cone", "propagation", "propagation+kniss", "sat_cone+AO", "reference", kPresetSweep})
        EXPECT_TRUE(methods.count(m)) << m;
    EXPECT_FALSE(methods.count("propagation+indirect"));
    ASSERT_EQ(plan.skipped.size(), 1u);
    EXPECT_EQ(plan.skipped[0], "/effects/indirect: the diffusion model takes its profile from one material, and volume 'b' has another "
                               "albedo or anisotropy than 'a': give them one, or take the kniss model (transport_color)");
}

// An environment light's median cut is a knob of each method that takes its lights: K and the
// remainder swept, each value a distinct render, and its floor counts as an ambient light for AO.
TEST(StudyPlan, AnEnvironmentLightsCutIsAKnobOfEveryFastMethod) {
    const std::string dir = test::tempDir("study_plan_environment");
    const std::string vdb = test::writeBall(dir);
    nlohmann::json j = ballScene(vdb, false);
    j["lights"].push_back({{"type", "environment"}, {"map", "sky.exr"}});
    const nlohmann::json base = sceneToJson(parseScene(j.dump(), "s.json", ""));
    const StudyPlan plan = planStudy(base, {1}, 1);
    std::map<std::string, std::vector<std::string>> knobs;   // "method knob" -> labels
    for (const auto& s : plan.sweeps) knobs[s.method + " " + s.knob] = s.labels;
    for (const char* method : {"raymarch", "sat_cone", "propagation+indirect"}) {
        EXPECT_EQ(knobs[std::string(method) + " lights.1.median_cut_lights"], (std::vector<std::string>{"1", "4", "16", "64"})) << method;
        EXPECT_EQ(knobs[std::string(method) + " lights.1.remainder"], (std::vector<std::string>{"floor", "none"})) << method;
    }
    EXPECT_TRUE(knobs.count("sat_cone+AO effects.ambient_occlusion.shells"));
    for (const auto& s : plan.sweeps)
        if (s.knob == "lights.1.median_cut_lights")
            EXPECT_EQ(studyScene(base, plan.configs[s.configs[3]]).lights[1].environment->median_cut_lights, 64);
}

TEST(StudyPlan, KeepsTheScenesOwnIndirectSettings) {
    const std::string vdb = test::writeBall(test::tempDir("study_plan_indirect"));
    nlohmann::json j = ballScene(vdb, false);
    j["effects"] = {{"indirect", {{"transport_color", {1.0, 0.6, 0.3}}, {"strength", 0.7}}}, {"shadows", "propagation"}};
    const nlohmann::json base = sceneToJson(parseScene(j.dump(), "s.json", ""));
    const StudyPlan plan = planStudy(base, {1}, 1);
    int indirect = 0;
    for (const auto& c : plan.configs) {
        const Scene s = studyScene(base, c);
        if (c.spp) continue;   // the reference traces all light; effects do not apply
        if (c.method != "propagation+kniss") {   // the scene's own model throughout
            EXPECT_FALSE(s.effects.indirect) << c.id();
            continue;
        }
        ++indirect;
        ASSERT_TRUE(s.effects.indirect);
        // The transport-colour sweep sets its own; its other settings stay the scene's.
        const bool sets_transport = c.id().find("transport_color=") != std::string::npos;
        if (c.id().find("transport_color=[0.9") != std::string::npos) {
            EXPECT_EQ(s.effects.indirect->transport_color, glm::vec3(0.9f)) << c.id();
        } else if (!sets_transport) {
            EXPECT_EQ(s.effects.indirect->transport_color, glm::vec3(1.0f, 0.6f, 0.3f)) << c.id();
        }
        if (c.id().find("strength=") == std::string::npos) {
            EXPECT_EQ(s.effects.indirect->strength, 0.7f) << c.id();
        }
    }
    EXPECT_GE(indirect, 14);

    // A scene with the diffusion model on (as voxlux writes it: "model" named): the transport-colour
    // sweep switches to Kniss's model rather than clash with it; every other config keeps diffusion.
    j["effects"] = {{"indirect", {{"strength", 0.7}}}, {"shadows", "propagation"}};
    const nlohmann::json diffusion_base = sceneToJson(parseScene(j.dump(), "s.json", ""));
    ASSERT_EQ(diffusion_base["effects"]["indirect"]["model"], "diffusion");
    const StudyPlan diffusion_plan = planStudy(diffusion_base, {1}, 1);
    int kniss = 0;
    for (const auto& c : diffusion_plan.configs) {
        const Scene s = studyScene(diffusion_base, c);
        if (!s.effects.indirect || c.spp) continue;
        const bool sets_transport = c.id().find("transport_color=") != std::string::npos;
        EXPECT_EQ(s.effects.indirect->model, sets_transport ? IndirectModel::Kniss : IndirectModel::Diffusion) << c.id();
        EXPECT_EQ(c.method, sets_transport ? "propagation+kniss" : "propagation+indirect") << c.id();
        kniss += sets_transport;
    }
    EXPECT_EQ(kniss, 4);
}

TEST(Study, MeasuresEveryConfigAndResumes) {
    const std::string dir = test::tempDir("study_run");
    const std::string vdb = test::writeBall(dir);
    const Scene scene = parseScene(ballScene(vdb, true).dump(), "s.json", "");
    StudyOptions o;
    o.out_dir = dir + "/out";
    o.spps = {1, 4};
    o.truth_spp = 64;
    o.command = "voxlux study s.json";
    std::ostringstream out;
    runStudy(scene, o, out);
    for (const char* f : {"study.csv", "chart.svg", "report.md", "truth.exr", "truth.json"})
        EXPECT_TRUE(std::filesystem::exists(o.out_dir + "/" + f)) << f;

    const nlohmann::json base = [&] {
        std::ifstream in(o.out_dir + "/truth.json");
        return nlohmann::json::parse(in);
    }();
    std::ifstream csv(o.out_dir + "/study.csv");
    std::string header;
    std::getline(csv, header);
    const auto rows = readStudyCsv(o.out_dir + "/study.csv", header.substr(2));
    const StudyPlan plan = planStudy(sceneToJson(scene), o.spps, 1);
    ASSERT_EQ(rows.size(), plan.configs.size());
    double ref1 = 0, ref4 = 0;
    int front = 0;
    for (const auto& r : rows) {
        EXPECT_TRUE(std::isfinite(r.rmse) && std::isfinite(r.delta_e)) << r.id;
        EXPECT_GT(r.seconds, 0.0) << r.id;
        front += r.front_rmse;
        if (r.spp == 1) ref1 = r.rmse;
        if (r.spp == 4) ref4 = r.rmse;
    }
    EXPECT_GE(front, 1);
    // Monte Carlo noise: four times the samples, half the error (the truth's own noise taken out).
    std::printf("  reference RMSE: 1 spp %.4f, 4 spp %.4f (ratio %.2f); truth noise %.4f\n", ref1, ref4, ref1 / ref4,
                base.value("noise_rmse", 0.0));
    EXPECT_NEAR(ref1 / ref4, 2.0, 0.4);
    std::ifstream report(o.out_dir + "/report.md");
    const std::string md((std::istreambuf_iterator<char>(report)), {});
    EXPECT_NE(md.find("Bias floors"), std::string::npos);
    // The crossover needs the reference's time to grow with its samples, which a render of a few
    // milliseconds need not show (the first pays for the thread pool): the report says which.
    if (fitReferenceCurve(rows)) EXPECT_NE(md.find("Crossover"), std::string::npos) << md;
    else EXPECT_NE(md.find("Too few reference renders for its error-time curve."), std::string::npos) << md;
    EXPECT_NE(md.find("| draft | propagation+indirect |"), std::string::npos);
    EXPECT_NE(md.find("| final | reference |"), std::string::npos);
    // Two stacked plots (RMSE, Delta E ITP), each with its Pareto front.
    std::ifstream chart(o.out_dir + "/chart.svg");
    const std::string svg((std::istreambuf_iterator<char>(chart)), {});
    size_t fronts = 0;
    for (size_t at = svg.find(">Pareto front<"); at != std::string::npos; at = svg.find(">Pareto front<", at + 1)) ++fronts;
    EXPECT_EQ(fronts, 2u);
    EXPECT_NE(svg.find("RMSE against time"), std::string::npos);
    EXPECT_NE(svg.find("perceptual error against time"), std::string::npos);

    // Run again: nothing is rendered.
    std::ostringstream again;
    runStudy(scene, o, again);
    EXPECT_NE(again.str().find("kept from an earlier run"), std::string::npos) << again.str();
    EXPECT_NE(again.str().find("resuming: " + std::to_string(rows.size()) + " of " + std::to_string(rows.size())),
              std::string::npos) << again.str();
    EXPECT_EQ(again.str().find("] "), std::string::npos) << again.str();   // no render lines

    // Another scene: measured from scratch.
    Scene denser = scene;
    denser.volume().material.density_scale = 12.0f;
    std::ostringstream other;
    runStudy(denser, o, other);
    EXPECT_EQ(other.str().find("resuming"), std::string::npos) << other.str();
    EXPECT_EQ(other.str().find("kept from an earlier run"), std::string::npos);
}

TEST(Study, BadSettingsAreRefused) {
    const std::string dir = test::tempDir("study_bad");
    const std::string vdb = test::writeBall(dir);
    const test::CliResult r = test::runCli("study " + vdb + " -o " + dir + "/out --truth-spp 3");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --truth-spp 3: must be even and at least 2\n");
    const test::CliResult spp = test::runCli("study " + vdb + " -o " + dir + "/out --truth-spp 64 --spp-list 1,64");
    EXPECT_EQ(spp.exit_code, 2);
    EXPECT_EQ(spp.err, "voxlux: error: --spp-list: 64 must be at least 1 and below --truth-spp (64)\n");
    EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

TEST(SvgPlot, NothingToPlotIsAnErrorNamingTheFile) {
    const std::string path = test::tempDir("svg") + "/empty.svg";
    try {
        writeLogLogSvg(path, {{"t", "x", "y", {{"s", "red", {{0.0, 1.0, ""}}}}}});
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": nothing to plot in 't'");
    }
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace voxlux
