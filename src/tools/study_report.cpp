#include "tools/study_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "tools/svg_plot.h"

namespace voxlux {
namespace {

// Keys that only pick the method (the method column says which).
bool picksMethod(const std::string& set) {
    const std::string key = set.substr(0, set.find('='));
    return key == "render.method" || key == "effects.shadows" || key == "effects.indirect" ||
           key == "effects.ambient_occlusion" || key == "render.reference.seed";
}

std::string fixed(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

const char* methodColor(const std::string& method) {
    static const std::map<std::string, const char*> colors = {
        {"unshadowed", "#7f7f7f"},           {"raymarch", "#1f77b4"},     {"raymarch+AO", "#17becf"},
        {"sat_cone", "#2ca02c"},             {"sat_cone+AO", "#98df8a"},  {"propagation", "#ff7f0e"},
        {"propagation+indirect", "#d62728"}, {"propagation+indirect+AO", "#e377c2"}, {"propagation+kniss", "#bcbd22"},
        {"reference", "#9467bd"}};
    auto it = colors.find(method);
    return it == colors.end() ? "#8c564b" : it->second;
}

const StudyRow* rowOf(const std::vector<StudyRow>& rows, const std::string& id) {
    for (const auto& r : rows)
        if (r.id == id) return &r;
    return nullptr;
}

}  // namespace

std::string studySettings(const std::string& id) {
    std::istringstream in(id);
    std::string out;
    for (std::string set; in >> set;)
        if (!picksMethod(set)) out += (out.empty() ? "" : " ") + set;
    return out.empty() ? "defaults" : out;
}

void writeStudyChart(const std::string& path, const StudyContext& context, const StudyPlan& plan,
                     const std::vector<StudyRow>& rows) {
    LogLogPlot by_rmse{context.title + ": RMSE against time", "seconds (CPU, every stage but reading the file)",
                       "RMSE of scene-linear RGB", {}};
    LogLogPlot by_delta_e{context.title + ": perceptual error against time", by_rmse.x_title,
                          "mean Delta E ITP (BT.2124)", {}};
    for (const auto& sweep : plan.sweeps) {
        PlotSeries rmse{sweep.method + (sweep.knob.empty() ? "" : ": " + sweep.knob), methodColor(sweep.method), {}};
        rmse.dashed = sweep.knob.find("step") != std::string::npos || sweep.knob.find("samples") != std::string::npos;
        rmse.dotted = sweep.knob.empty() || sweep.knob.find("angle") != std::string::npos;
        PlotSeries delta_e = rmse;
        for (size_t i = 0; i < sweep.configs.size(); ++i) {
            const StudyRow* r = rowOf(rows, plan.configs[sweep.configs[i]].id());
            if (!r) continue;
            const std::string label = sweep.knob.empty() && sweep.labels[i] == "-" ? "" : sweep.labels[i];
            rmse.points.push_back({r->seconds, r->rmse, label});
            delta_e.points.push_back({r->seconds, r->delta_e, label});
        }
        if (rmse.points.empty()) continue;
        if (sweep.method == kPresetSweep) {   // three settings, not a sweep: points, labelled
            rmse.line = delta_e.line = false;
            rmse.color = delta_e.color = "black";
        }
        by_rmse.series.push_back(rmse);
        by_delta_e.series.push_back(delta_e);
    }
    auto front = [&](bool StudyRow::*on, double StudyRow::*error) {
        PlotSeries s{"Pareto front", "black", {}};
        s.markers = false;
        s.width = 3;
        for (const auto& r : rows)
            if (r.*on) s.points.push_back({r.seconds, r.*error, ""});
        std::sort(s.points.begin(), s.points.end(), [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
        return s;
    };
    by_rmse.series.push_back(front(&StudyRow::front_rmse, &StudyRow::rmse));
    by_delta_e.series.push_back(front(&StudyRow::front_delta_e, &StudyRow::delta_e));
    if (auto curve = fitReferenceCurve(rows)) {
        PlotSeries fit{"reference fit: t0 + k spp, sigma / sqrt(spp)", methodColor("reference"), {}};
        fit.markers = false;
        fit.dotted = true;
        for (double spp = 1; spp <= context.truth.spp; spp *= 2)
            fit.points.push_back({curve->t0 + curve->k * spp, curve->sigma / std::sqrt(spp), ""});
        by_rmse.series.push_back(fit);
    }
    // The truth's own noise: errors near this line are not resolved.
    double t_lo = 1e300, t_hi = 0;
    for (const auto& r : rows) t_lo = std::min(t_lo, r.seconds), t_hi = std::max(t_hi, r.seconds);
    if (context.truth.noise_delta_e > 0 && t_hi > 0) {
        PlotSeries noise{"noise of the ground truth", "#bbbbbb", {{t_lo, context.truth.noise_delta_e, ""},
                                                                 {t_hi, context.truth.noise_delta_e, ""}}};
        noise.markers = false;
        noise.dashed = true;
        by_delta_e.series.push_back(noise);
    }
    writeLogLogSvg(path, {by_rmse, by_delta_e});
}

std::string studyReport(const StudyContext& context, const StudyPlan& plan, const std::vector<StudyRow>& rows,
                        const std::string& chart) {
    std::ostringstream md;
    md << "### " << context.title << "\n\n"
       << "Measured with `" << context.command << "` at " << context.width << "x" << context.height
       << ". Ground truth: the reference at " << context.truth.spp << " samples per pixel ("
       << fixed("%.0f", context.truth.seconds) << " s), in two halves of independent seeds; its own noise, RMSE "
       << fixed("%.2g", context.truth.noise_rmse) << " (taken out of every RMSE below) and Delta E ITP about "
       << fixed("%.2g", context.truth.noise_delta_e) << " (left in).\n\n"
       << "![error against time](" << chart << ")\n\n";

    md << "| method | settings | seconds | RMSE | Delta E ITP | Pareto front |\n|---|---|---|---|---|---|\n";
    std::vector<StudyRow> sorted = rows;
    std::stable_sort(sorted.begin(), sorted.end(), [](const StudyRow& a, const StudyRow& b) { return a.seconds < b.seconds; });
    for (const auto& r : sorted)
        md << "| " << r.method << " | " << studySettings(r.id) << " | " << fixed("%.3f", r.seconds) << " | "
           << fixed("%.4g", r.rmse) << " | " << fixed("%.3g", r.delta_e) << " | "
           << (r.front_rmse && r.front_delta_e ? "both" : r.front_rmse ? "RMSE" : r.front_delta_e ? "Delta E" : "")
           << " |\n";

    md << "\nBias floors: each method's lowest RMSE over its settings, which more time does not lower.\n\n"
       << "| method | lowest RMSE | Delta E ITP there | settings | seconds |\n|---|---|---|---|---|\n";
    for (const auto& f : biasFloors(rows))
        md << "| " << f.method << " | " << fixed("%.4g", f.rmse) << " | " << fixed("%.3g", f.delta_e) << " | "
           << studySettings(f.id) << " | " << fixed("%.3f", f.seconds) << " |\n";

    md << "\nThe quality presets (`--quality`) on this scene:\n\n"
       << "| preset | method | seconds | RMSE | Delta E ITP |\n|---|---|---|---|---|\n";
    for (const auto& sweep : plan.sweeps) {
        if (sweep.method != kPresetSweep) continue;
        for (size_t i = 0; i < sweep.configs.size(); ++i)
            if (const StudyRow* r = rowOf(rows, plan.configs[sweep.configs[i]].id()))
                md << "| " << sweep.labels[i] << " | " << r->method << " | " << fixed("%.3f", r->seconds) << " | "
                   << fixed("%.4g", r->rmse) << " | " << fixed("%.3g", r->delta_e) << " |\n";
    }

    const auto curve = fitReferenceCurve(rows);
    if (!curve) {
        md << "\nToo few reference renders for its error-time curve.\n";
        return md.str();
    }
    md << "\nThe reference's curve, fitted to its renders: seconds = " << fixed("%.3f", curve->t0) << " + "
       << fixed("%.4f", curve->k) << " x spp, RMSE = " << fixed("%.4g", curve->sigma) << " / sqrt(spp).\n\n";
    const Crossover c = crossoverOf(rows, *curve);
    if (c.seconds > 0)
        md << "Crossover: below " << fixed("%.3g", c.seconds)
           << " s an approximation beats the reference at equal time; above it the reference is more accurate.\n\n";
    else
        md << "Crossover: none: at every time the reference is at least as accurate as every approximation.\n\n";
    md << "At equal RMSE, the approximations on their own Pareto front against the reference:\n\n"
       << "| method | settings | seconds | RMSE | reference needs (s) | speed-up |\n|---|---|---|---|---|---|\n";
    for (const auto& r : approximationFront(rows)) {
        const double t_ref = curve->secondsFor(r.rmse);
        md << "| " << r.method << " | " << studySettings(r.id) << " | " << fixed("%.3f", r.seconds) << " | "
           << fixed("%.4g", r.rmse) << " | " << fixed("%.3g", t_ref) << " | " << fixed("%.2g", t_ref / r.seconds) << "x |\n";
    }
    const StudyRow* least = rowOf(rows, c.min_speedup_id);
    md << "\nThe least speed-up is " << fixed("%.2g", c.min_speedup) << "x (" << (least ? least->method + ", " : "")
       << studySettings(c.min_speedup_id) << "); the target is 50x: " << (c.min_speedup >= 50 ? "met" : "not met") << ".\n";
    return md.str();
}

}  // namespace voxlux
