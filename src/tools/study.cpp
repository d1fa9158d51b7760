#include "tools/study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>

#include "grade/color_pipeline.h"
#include "core/error.h"
#include "core/progress.h"
#include "io/exr_reader.h"
#include "io/exr_writer.h"
#include "core/frame_pattern.h"
#include "tools/image_metrics.h"
#include "render/renderer.h"
#include "render/write_stage.h"
#include "scene/scene_json.h"
#include "tools/study_plan.h"
#include "tools/study_report.h"
#include "tools/study_results.h"

namespace voxlux {
namespace fs = std::filesystem;
nlohmann::json studyBase(const Scene& scene) {
    nlohmann::json j = sceneToJson(scene);
    j["render"]["backend"] = "cpu";
    for (const char* key : {"output_space", "grade", "display", "view"}) j["color"].erase(key);
    j["output"]["aovs"] = nlohmann::json::array();
    j["output"]["preview"] = "";
    j["output"]["deep"] = false;   // the reference makes none, and the march's timing is of the image
    return j;
}

std::optional<int> studyFrame(const Scene& scene) {
    if (!hasFramePattern(scene.volume().path)) return std::nullopt;
    if (!scene.volume().frames)
        throw InputError(scene.volume().path + ": path has a #### frame pattern; set volume.frames or pass --frames");
    return scene.volume().frames->first();
}

namespace {

// Every stage but reading the file and the colour config, which are the same for every method.
double computeSeconds(const FrameResult& r) {
    double s = 0;
    for (const auto& [stage, seconds] : r.stage_seconds)
        if (stage != "load" && stage != "color_space" && stage != "color_transforms") s += seconds;
    return s;
}

struct Measured {
    RenderImage image;
    double seconds = 0;
};

Measured renderTimed(const Scene& scene, std::optional<int> frame, int repeats) {
    Measured m;
    m.seconds = 1e300;
    for (int i = 0; i < repeats; ++i) {
        Renderer renderer(scene);   // fresh: nothing reused from an earlier config
        FrameResult r = renderer.render(frame, false);
        m.seconds = std::min(m.seconds, computeSeconds(r));
        m.image = std::move(r.image);
    }
    return m;
}

struct Truth {
    RenderImage image;
    StudyTruth info;
};

// The ground truth: kept in the study folder and reused while the scene and sample count are
// unchanged. Two halves with their own seeds measure its noise.
Truth groundTruth(const nlohmann::json& base, const std::string& hash, const StudyOptions& o, std::optional<int> frame,
                  const glm::mat3& working_to_xyz, ProgressTask& progress, std::ostream& out) {
    const fs::path dir(o.out_dir);
    const std::string exr = (dir / "truth.exr").string(), json = (dir / "truth.json").string();
    if (!o.fresh && fs::exists(exr) && fs::exists(json)) {
        std::ifstream in(json);
        const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
        if (!j.is_discarded() && j.value("scene", "") == hash && j.value("spp", 0) == o.truth_spp) {
            Truth t{readExrRgba(exr), {o.truth_spp, j.value("seconds", 0.0), j.value("noise_rmse", 0.0), j.value("noise_delta_e", 0.0)}};
            out << "ground truth: " << exr << " (" << o.truth_spp << " spp, kept from an earlier run)\n";
            return t;
        }
    }
    const int seed = base["render"]["reference"].value("seed", 1);
    Measured half[2];
    for (int h = 0; h < 2; ++h) {
        progress.describe("ground truth, half " + std::to_string(h + 1) + " of 2");
        StudyConfig c{"reference", {"render.method=reference", "render.reference.spp=" + std::to_string(o.truth_spp / 2),
                                    "render.reference.seed=" + std::to_string(truthHalfSeed(seed, h))}, o.truth_spp / 2};
        half[h] = renderTimed(studyScene(base, c), frame, 1);
    }
    Truth t;
    t.image = meanOfHalves(half[0].image, half[1].image);
    // The mean's error against the noise-free image is half the halves' difference.
    t.info = {o.truth_spp, half[0].seconds + half[1].seconds, std::sqrt(halvesNoiseMse(half[0].image, half[1].image)),
              0.5 * meanDeltaEItp(half[0].image, half[1].image, working_to_xyz)};
    OutputSpec spec;
    spec.pixel_type = PixelType::Float;
    writeExr(exr, t.image, spec, ExrMetadata{});
    writeFileAtomically(json, nlohmann::json({{"scene", hash}, {"spp", o.truth_spp}, {"seconds", t.info.seconds},
                                               {"noise_rmse", t.info.noise_rmse}, {"noise_delta_e", t.info.noise_delta_e}})
                                      .dump(2) + "\n");
    clearProgressLine();
    out << "ground truth: " << exr << " (" << o.truth_spp << " spp in " << clockText(t.info.seconds) << ", noise RMSE "
        << t.info.noise_rmse << ")\n";
    return t;
}

}  // namespace

void runStudy(const Scene& scene, const StudyOptions& o, std::ostream& out) {
    if (o.truth_spp < 2 || o.truth_spp % 2) throw InputError("--truth-spp " + std::to_string(o.truth_spp) + ": must be even and at least 2");
    for (int spp : o.spps)
        if (spp < 1 || spp >= o.truth_spp)
            throw InputError("--spp-list: " + std::to_string(spp) + " must be at least 1 and below --truth-spp (" +
                             std::to_string(o.truth_spp) + ")");
    const nlohmann::json base = studyBase(scene);
    const Scene base_scene = parseScene(base.dump(), "study scene", "");
    const std::optional<int> frame = studyFrame(base_scene);
    const StudyPlan plan = planStudy(base, o.spps, base_scene.render.reference.seed);
    for (const std::string& why : plan.skipped) out << "skipped, as the scene refuses it: " << why << "\n";
    // The scene's hash leaves the frames out (a frame's outputs carry one hash wherever it
    // renders); the study's truth and rows are of one frame, so its key names it.
    const std::string hash = frame ? hashText(sceneHash(base_scene) + ":frame " + std::to_string(*frame)) : sceneHash(base_scene);

    const ColorPipeline color = buildColorPipeline(base_scene.color, false);
    if (!color.xyz_to_working)
        throw InputError(color.config_source + ": has no cie_xyz_d65_interchange role, which the study's Delta E ITP needs");
    const glm::mat3 working_to_xyz = glm::inverse(*color.xyz_to_working);

    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    if (ec) throw InputError(o.out_dir + ": cannot create the study folder (" + ec.message() + ")");
    const std::string csv = (fs::path(o.out_dir) / "study.csv").string();
    const std::string header = "voxlux study: scene " + hash + ", truth " + std::to_string(o.truth_spp) + " spp";

    ProgressTask progress("study", int64_t(plan.configs.size()), "renders");
    const Truth truth = groundTruth(base, hash, o, frame, working_to_xyz, progress, out);

    std::vector<StudyRow> rows = o.fresh ? std::vector<StudyRow>{} : readStudyCsv(csv, header);
    std::string kept = studyCsvHeader(header);
    std::vector<StudyRow> known;
    for (const auto& c : plan.configs)
        for (const auto& r : rows)
            if (r.id == c.id()) known.push_back(r), kept += studyCsvRow(r);
    rows = known;
    if (!rows.empty()) out << "resuming: " << rows.size() << " of " << plan.configs.size() << " renders kept from " << csv << "\n";
    writeFileAtomically(csv, kept);
    progress.advance(int64_t(rows.size()));

    // Time left: a reference render costs its share of the truth's time per sample; the others
    // cost what they have cost on average so far.
    const double per_sample = truth.info.seconds / truth.info.spp;
    double approx_sum = 0;
    int approx_n = 0;
    auto expected = [&](const StudyConfig& c) { return c.spp ? c.spp * per_sample : approx_n ? approx_sum / approx_n : 2.0; };

    auto measured = [&](const StudyConfig& c) {
        return std::any_of(rows.begin(), rows.end(), [&](const StudyRow& r) { return r.id == c.id(); });
    };

    std::ofstream append(csv, std::ios::app);
    for (size_t i = 0; i < plan.configs.size(); ++i) {
        const StudyConfig& c = plan.configs[i];
        if (measured(c)) continue;
        double left = 0;
        for (size_t k = i; k < plan.configs.size(); ++k)
            if (!measured(plan.configs[k])) left += expected(plan.configs[k]) * o.repeats;
        progress.estimateLeft(left);
        progress.describe(c.method + ": " + studySettings(c.id()));
        const Measured m = renderTimed(studyScene(base, c), frame, o.repeats);
        StudyRow r{c.id(), c.method, c.spp, m.seconds,
                   std::sqrt(std::max(0.0, meanSquaredError(m.image, truth.image) - truth.info.noise_rmse * truth.info.noise_rmse)),
                   meanDeltaEItp(m.image, truth.image, working_to_xyz)};
        if (!c.spp) approx_sum += m.seconds, ++approx_n;
        rows.push_back(r);
        append << studyCsvRow(r) << std::flush;
        char line[200];
        std::snprintf(line, sizeof line, "[%2zu/%zu] %8.3f s  RMSE %.4g  Delta E ITP %.3g  ", rows.size(), plan.configs.size(),
                      r.seconds, r.rmse, r.delta_e);
        progress.advance();
        clearProgressLine();
        out << line << c.method << ": " << studySettings(c.id()) << "\n" << std::flush;
    }
    append.close();

    markParetoFronts(rows);
    std::string all = studyCsvHeader(header);
    for (const auto& r : rows) all += studyCsvRow(r);
    writeFileAtomically(csv, all);
    StudyContext context{o.title.empty() ? fs::path(scene.volume().path).filename().string() : o.title, o.command,
                         base_scene.render.width, base_scene.render.height, truth.info};
    const std::string chart = (fs::path(o.out_dir) / "chart.svg").string();
    writeStudyChart(chart, context, plan, rows);
    const std::string report = (fs::path(o.out_dir) / "report.md").string();
    writeFileAtomically(report, studyReport(context, plan, rows, "chart.svg"));
    out << "wrote " << csv << ", " << chart << " and " << report << "\n";
}

}  // namespace voxlux
