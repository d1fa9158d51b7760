#include "tools/calibrate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "core/error.h"
#include "io/exr_reader.h"
#include "render/renderer.h"
#include "tools/image_metrics.h"
#include "tools/study.h"
#include "tools/study_plan.h"

namespace voxlux {
namespace {

// A given truth must be a finite, non-black image of the scene's framing.
void checkTruth(const RenderImage& truth, const Scene& scene, const std::string& path) {
    if (truth.width < 8 || truth.height < 8)
        throw InputError(path + ": " + std::to_string(truth.width) + "x" + std::to_string(truth.height) +
                         " is too small to fit (at least 8x8)");
    // The same aspect as the scene, to within a pixel's rounding: another framing is another image.
    if (std::abs(double(truth.width) * scene.render.height - double(truth.height) * scene.render.width) >=
        double(std::max(scene.render.width, scene.render.height)))
        throw InputError(path + ": " + std::to_string(truth.width) + "x" + std::to_string(truth.height) +
                         " does not have the scene's aspect (" + std::to_string(scene.render.width) + "x" +
                         std::to_string(scene.render.height) + ")");
    size_t bad = 0;
    bool lit = false;
    for (const auto& p : truth.pixels)
        for (int c = 0; c < 3; ++c) {
            bad += !std::isfinite(p.rgba[c]);
            lit = lit || p.rgba[c] != 0.0f;
        }
    if (bad) throw InputError(path + ": " + std::to_string(bad) + " colour values are not finite");
    if (!lit) throw InputError(path + ": the image is black (or has no R, G, B channels): nothing to fit");
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// One march's fit: the strength that minimises the RGB RMSE against the truth, and that MSE.
struct Fit {
    float strength = 0.0f;
    double mse = 0.0;
};

// The beauty is base + m * indirect, where the indirect AOV was rendered at `strength`: the best
// m >= 0 is <truth - base, indirect> / <indirect, indirect>.
Fit fitStrength(const RenderImage& march, const RenderImage& truth, float strength) {
    double cross = 0.0, power = 0.0;
    for (size_t i = 0; i < march.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double ind = march.pixels[i].indirect[c];
            const double base = march.pixels[i].rgba[c] - ind;
            cross += (truth.pixels[i].rgba[c] - base) * ind;
            power += ind * ind;
        }
    const double m = power > 0.0 ? std::max(0.0, cross / power) : 1.0;
    double error = 0.0;
    for (size_t i = 0; i < march.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double ind = march.pixels[i].indirect[c];
            const double d = march.pixels[i].rgba[c] - ind + m * ind - truth.pixels[i].rgba[c];
            error += d * d;
        }
    return {float(strength * m), error / (3.0 * double(std::max<size_t>(march.pixels.size(), 1)))};
}

}  // namespace

Calibration calibrate(const Scene& scene, const CalibrateOptions& o, std::ostream& out) {
    if (scene.render.method != RenderMethod::March || scene.effects.shadows != ShadowMethod::Propagation ||
        !scene.effects.indirect)
        throw InputError("calibrate: fits effects.indirect, which needs render.method \"march\", effects.shadows "
                         "\"propagation\" and effects.indirect (--quality preview sets all three)");
    if (o.spp < 2 || o.spp % 2 != 0) throw InputError("calibrate: --reference-spp must be even and at least 2 (two halves)");
    if (o.max_side < 8) throw InputError("calibrate: --max-side must be at least 8 pixels");
    Calibration cal;
    // Measured as the study measures: CPU, ungraded (a grade is not linear in the indirect light),
    // a sequence's first frame.
    Scene reduced = studyScene(studyBase(scene), StudyConfig{});
    const std::optional<int> frame = studyFrame(scene);
    RenderImage truth;
    if (o.truth) {
        truth = readExrRgba(*o.truth);
        checkTruth(truth, scene, *o.truth);
        reduced.render.width = truth.width;
        reduced.render.height = truth.height;
    } else {
        const double scale = std::min(1.0, double(o.max_side) / std::max(scene.render.width, scene.render.height));
        reduced.render.width = std::max(1, int(std::lround(scene.render.width * scale)));
        reduced.render.height = std::max(1, int(std::lround(scene.render.height * scale)));
        // In two halves of independent seeds, so that the truth's own noise can be taken out.
        const auto t = std::chrono::steady_clock::now();
        RenderImage half[2];
        for (int h = 0; h < 2; ++h) {
            Scene reference = reduced;
            reference.render.method = RenderMethod::Reference;
            reference.render.reference.spp = o.spp / 2;
            reference.render.reference.seed = truthHalfSeed(scene.render.reference.seed, h);
            half[h] = Renderer(reference).render(frame, false).image;
        }
        truth = meanOfHalves(half[0], half[1]);
        cal.truth_noise_mse = halvesNoiseMse(half[0], half[1]);
        cal.truth_seconds = secondsSince(t);
        char line[160];
        std::snprintf(line, sizeof line, "reference: %dx%d, %d spp in two halves, %.3g s, its noise RMSE %.3g (taken out below)\n",
                      reduced.render.width, reduced.render.height, o.spp, cal.truth_seconds,
                      std::sqrt(cal.truth_noise_mse));
        out << line;
    }
    cal.width = reduced.render.width;
    cal.height = reduced.render.height;

    const auto t = std::chrono::steady_clock::now();
    Renderer renderer(reduced);   // one renderer: a new indirect setting re-runs propagation and the march only
    auto march = [&](const Indirect& in) {
        Scene s = reduced;
        s.effects.indirect = in;
        renderer.setScene(s);
        ++cal.marches;
        return renderer.render(frame, false).image;
    };
    // RMSE against the noise-free image: the truth's noise is added to every MSE measured against it.
    auto rmse = [&](double mse) { return std::sqrt(std::max(0.0, mse - cal.truth_noise_mse)); };
    const Indirect own = *scene.effects.indirect;
    cal.rmse_before = rmse(meanSquaredError(march(own), truth));
    auto report = [&](const char* what, const Indirect& in, double error) {
        char line[200];
        std::snprintf(line, sizeof line, "%s: strength %.4g%s, RMSE %.5g\n", what, double(in.strength),
                      in.model == IndirectModel::Kniss ? (", transport colour " + std::to_string(in.transport_color.x)).c_str() : "",
                      error);
        out << line;
    };
    report("the scene's own", own, cal.rmse_before);

    // The diffusion model: the strength alone.
    Indirect diffusion = own;
    diffusion.model = IndirectModel::Diffusion;
    diffusion.strength = 1.0f;
    const Fit d = fitStrength(march(diffusion), truth, diffusion.strength);
    diffusion.strength = d.strength;
    report("diffusion", diffusion, rmse(d.mse));

    // Kniss's model: a grey transport colour by golden section over (0.02, 0.99), each with its
    // best strength (taken to be unimodal in it: the studies' transport sweeps are).
    Indirect kniss = own;
    kniss.model = IndirectModel::Kniss;
    auto kniss_at = [&](double transport) {
        kniss.transport_color = glm::vec3(float(transport));
        kniss.strength = 1.0f;
        const Fit f = fitStrength(march(kniss), truth, 1.0f);
        return std::make_pair(f.mse, f.strength);
    };
    const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
    double lo = 0.02, hi = 0.99;
    double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
    auto fa = kniss_at(a), fb = kniss_at(b);
    for (int step = 0; step < 14; ++step) {
        if (fa.first <= fb.first) {
            hi = b;
            b = a;
            fb = fa;
            a = hi - golden * (hi - lo);
            fa = kniss_at(a);
        } else {
            lo = a;
            a = b;
            fa = fb;
            b = lo + golden * (hi - lo);
            fb = kniss_at(b);
        }
    }
    const bool take_a = fa.first <= fb.first;
    kniss.transport_color = glm::vec3(float(take_a ? a : b));
    kniss.strength = take_a ? fa.second : fb.second;
    const double kniss_mse = take_a ? fa.first : fb.first;
    report("kniss", kniss, rmse(kniss_mse));

    // Chosen on the raw MSE: with the noise taken out, both can clamp to 0 where it exceeds the error.
    const bool diffusion_wins = d.mse <= kniss_mse;
    cal.indirect = diffusion_wins ? diffusion : kniss;
    cal.rmse_after = rmse(diffusion_wins ? d.mse : kniss_mse);
    if (!std::isfinite(cal.indirect.strength))
        throw InputError("calibrate: the fit found no finite strength (the scene's indirect light is too faint to fit)");
    cal.fit_seconds = secondsSince(t);
    return cal;
}

}  // namespace voxlux
