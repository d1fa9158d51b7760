// `voxlux calibrate SCENE.json`: fits the indirect light of the propagation method to a Monte Carlo
// reference of the scene, so that a whole sequence renders fast at the calibrated accuracy
// (docs/accuracy.md, "Calibration"). Costs one reference render at reduced resolution (or none,
// given a truth image) and about twenty marches at that resolution.
//
// The march's beauty is linear in effects.indirect.strength (the indirect AOV scales with it), so
// for each candidate the strength that minimises the RMSE against the truth is a closed-form
// least-squares solution. The diffusion model has no other parameter; Kniss's has the transport
// colour, searched (grey) by golden section with the strength solved at each step. The model with
// the lower RMSE is kept.
#pragma once
#include <iosfwd>
#include <optional>
#include <string>

#include "scene/scene.h"

namespace voxlux {

struct CalibrateOptions {
    std::string output;                  // the calibrated scene .json
    std::optional<std::string> truth;    // a reference image to fit (RGBA EXR, the scene's aspect) instead of rendering one
    int spp = 256;                       // the reference's samples per pixel (even: two halves)
    int max_side = 256;                  // the reduced resolution's longest side (pixels)
};

struct Calibration {
    Indirect indirect;                   // the fitted settings
    double rmse_before = 0.0;            // the scene's own settings against the truth (its noise taken out)
    double rmse_after = 0.0;
    double truth_noise_mse = 0.0;        // the rendered truth's own noise (0 for a given truth)
    double truth_seconds = 0.0;          // the reference render (0 with a given truth)
    double fit_seconds = 0.0;
    int marches = 0;
    int width = 0, height = 0;           // the resolution fitted at
};

// Fits `scene`'s effects.indirect (it must have shadows "propagation" and indirect light);
// reports each step to `out`. Throws InputError.
Calibration calibrate(const Scene& scene, const CalibrateOptions& options, std::ostream& out);

}  // namespace voxlux
