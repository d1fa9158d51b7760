// What `voxlux study` writes besides the CSV: the chart of error against time (drawn here, as
// SVG) and the Markdown report that docs/accuracy.md is made of.
#pragma once
#include <string>
#include <vector>

#include "tools/study_plan.h"
#include "tools/study_results.h"

namespace voxlux {

struct StudyTruth {
    int spp = 0;
    double seconds = 0;
    double noise_rmse = 0;               // of the truth itself, from its two halves
    double noise_delta_e = 0;            // Delta E_ITP of the truth against the noise-free image, estimated
};

struct StudyContext {
    std::string title;                   // the scene, as the report names it
    std::string command;                 // the command that measured it
    int width = 0, height = 0;
    StudyTruth truth;
};

// The settings of a config that differ from its method's defaults, e.g. "effects.cone.samples=50".
std::string studySettings(const std::string& id);

// Two log-log plots, RMSE and Delta E_ITP against seconds: a line per sweep, the reference's
// fitted curve, the truth's noise level and the Pareto front.
void writeStudyChart(const std::string& path, const StudyContext& context, const StudyPlan& plan,
                     const std::vector<StudyRow>& rows);

// The Markdown report: every render, the bias floor of each method, the quality presets, the
// reference's curve and the crossover. `chart` is the chart's path as the report links it.
std::string studyReport(const StudyContext& context, const StudyPlan& plan, const std::vector<StudyRow>& rows,
                        const std::string& chart);

}  // namespace voxlux
