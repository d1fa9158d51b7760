// `voxlux study SCENE.json`: renders the scene with every lighting method and quality knob and
// with the Monte Carlo reference, measures each against a long-converged reference, and writes
// the CSV, the chart and the report (docs/accuracy.md). Resumes where a stopped run left off.
#pragma once
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace voxlux {

struct StudyOptions {
    std::string out_dir = "study";
    std::string title;                   // the report's name for the scene ("" = the volume file's name)
    std::string command;                 // as the report quotes it
    std::vector<int> spps{1, 4, 16, 64, 256};
    int truth_spp = 1024;                // the ground truth, in two halves of independent seeds
    int repeats = 1;                     // renders per config; the fastest counts
    bool fresh = false;                  // ignore what an earlier run measured
};

// The scene as every measurement starts from: CPU, ungraded, in the working space, no files
// written. Errors are measured on the scene-linear beauty, before any look or display transform.
nlohmann::json studyBase(const Scene& scene);

// The frame a measurement renders: a sequence's first (volume.frames), or none for one file.
std::optional<int> studyFrame(const Scene& scene);

// The seed of half `half` (0 or 1) of a ground truth rendered in two halves from the scene's
// reference seed `seed`: far from it and from each other, so the halves' noise is independent.
inline int truthHalfSeed(int seed, int half) { return seed + 1000003 * (half + 1); }

// Writes <out_dir>/study.csv, truth.exr, truth.json, chart.svg and report.md, and one line per
// render to `out`; progress through core/progress.h. Throws InputError.
void runStudy(const Scene& scene, const StudyOptions& options, std::ostream& out);

}  // namespace voxlux
