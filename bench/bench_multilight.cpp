// What many lights cost in the illumination-volume propagation, and what editing one of them
// costs (Sunden & Ropinski 2015: coherence-based propagation of several lights in one pass, and
// selective updates that take out and put back only the light that changed);
// docs/performance-multilight.md.
//
// On the shared smoke (arnold-usd/smoke.vdb, grid "density"), shadows "propagation", direct light
// only, CPU backend, at two illumination resolutions (1x: light_resolution = the active voxels'
// longest side; 1/4: a quarter of that per axis), for N = 1, 2, 4, 8, 16, 40 lights in three rigs:
//   same direction  N directional lights along one oblique direction, each its own colour
//                   (the paper's Fig. 10 scaling test);
//   spread          N directional lights with directions spread evenly over the sphere
//                   (a Fibonacci sphere), each its own colour;
//   point           N point lights on a sphere just outside the volume's bounding box (N <= 8).
// For each rig and N, through LightRig::apply():
//   1. an entire update on a fresh Renderer (nothing reused), sequential (one pass per light,
//      effects.propagation.coherent = false) and coherent (one pass per propagation direction):
//      the "propagation" stage, best of 3 (the point rig at 1x: best of 2); then the per-light
//      cost of each (least-squares slope of time against N) and their ratio;
//   2. on the coherent renderer, moving one light 3 degrees (best of 3 moves, to +3, -3, +3) and
//   3. toggling one light off (best of 3; toggled back on between runs, timed apart),
//      with what the illumination stage chose to run (mode, sweeps, passes, slices): the stage
//      decides between selective and entire by its cost estimate, nothing is forced. With 8
//      lights, also an entire update on that live renderer (no allocation), forced by a settings
//      change the image does not see, to set the edits against like for like.
// Then, at 1x, calibration figures for that estimate: ns per cell of one pass with one
// directional light, of each further directional light in a coherent pass and of each further
// pass, of a point-light sweep, and of a directional light with indirect light on.
// Prints markdown tables on stdout and progress on stderr; it asserts nothing. About 2.5 minutes
// on the 2-core machine when it is quiet, 3.5-4 with other work running; --quick (one run per
// figure, N = 1, 2, 8, no point rig at 1x) 13-25 s.
//
//   build/voxlux_bench_multilight [--data DIR] [--quick]
#include <algorithm>
#include <chrono>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "source_dir.h"
#include "bench_timing.h"
#include "render/light_rig.h"
#include "lighting/propagation/propagation_stages.h"
#include "render/renderer.h"
#include "volume/vdb_loader.h"

namespace {

using namespace voxlux;

const auto kStart = std::chrono::steady_clock::now();

// A progress line on stderr, with the seconds since the start.
__attribute__((format(printf, 1, 2))) void progress(const char* format, ...) {
    std::fprintf(stderr, "[%5.1f s] ", std::chrono::duration<double>(std::chrono::steady_clock::now() - kStart).count());
    va_list args;
    va_start(args, format);
    std::vfprintf(stderr, format, args);
    va_end(args);
    std::fprintf(stderr, "\n");
}

// The volume's world-space bounding box (of its active voxels) and its longest side in voxels.
struct Volume {
    std::string file;
    glm::vec3 lo{0.0f}, hi{0.0f};
    int longest = 0;   // active voxels along the longest side
    glm::vec3 centre() const { return 0.5f * (lo + hi); }
    float halfDiagonal() const { return 0.5f * glm::length(hi - lo); }
};

Volume measureVolume(const std::string& file) {
    VolumeSpec spec;
    spec.path = file;
    const LoadedVolume v = loadVolume(file, spec);
    const openvdb::CoordBBox box = v.density->evalActiveVoxelBoundingBox();
    Volume out;
    out.file = file;
    out.longest = std::max({box.dim().x(), box.dim().y(), box.dim().z()});
    out.lo = glm::vec3(1e30f);
    out.hi = glm::vec3(-1e30f);
    const glm::vec3 a(box.min().x(), box.min().y(), box.min().z()), b(box.max().x() + 1, box.max().y() + 1, box.max().z() + 1);
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 corner((k & 1) ? b.x : a.x, (k & 2) ? b.y : a.y, (k & 4) ? b.z : a.z);
        const glm::vec3 w = glm::vec3(v.index_to_world * glm::vec4(corner, 1.0f));
        out.lo = glm::min(out.lo, w);
        out.hi = glm::max(out.hi, w);
    }
    return out;
}

// A saturated colour of hue h (0..1): the lights of a rig are told apart by colour.
glm::vec3 hue(float h) {
    const glm::vec3 k = glm::abs(glm::fract(glm::vec3(h) + glm::vec3(0.0f, 2.0f / 3.0f, 1.0f / 3.0f)) * 6.0f - 3.0f) - 1.0f;
    return glm::mix(glm::vec3(1.0f), glm::clamp(k, 0.0f, 1.0f), 0.6f);
}

// The oblique direction of the "same direction" rig: principal axis -y, some 15 degrees from the
// nearest tie with another axis.
const glm::vec3 kOblique = glm::normalize(glm::vec3(-0.45f, -0.8f, -0.4f));

// n points evenly over the unit sphere (Fibonacci), turned by a fixed rotation: unturned, the
// lone point of n = 1 would lie on the x axis.
std::vector<glm::vec3> fibonacciSphere(int n) {
    const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), 0.37f, glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f))));
    const float golden = 2.39996323f;
    std::vector<glm::vec3> out;
    for (int i = 0; i < n; ++i) {
        const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n), r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        out.push_back(turn * glm::vec3(r * std::cos(golden * float(i)), y, r * std::sin(golden * float(i))));
    }
    return out;
}

// `v` turned by `degrees` about an axis perpendicular to it.
glm::vec3 turned(glm::vec3 v, float degrees) {
    glm::vec3 axis = glm::cross(v, glm::vec3(0.0f, 1.0f, 0.0f));
    if (glm::length(axis) < 1e-3f * glm::length(v)) axis = glm::cross(v, glm::vec3(1.0f, 0.0f, 0.0f));
    return glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(axis)) * glm::vec4(v, 0.0f));
}

enum class Rig { SameDirection, Spread, Point };
const char* rigName(Rig r) { return r == Rig::SameDirection ? "same direction" : r == Rig::Spread ? "spread" : "point"; }

std::vector<Light> rigLights(Rig rig, int n, const Volume& vol) {
    std::vector<Light> out;
    const std::vector<glm::vec3> sphere = fibonacciSphere(n);
    const float radius = 1.05f * vol.halfDiagonal();   // the bounding box's corners are at 1.0
    for (int i = 0; i < n; ++i) {
        Light l;
        l.name = "light" + std::to_string(i);
        l.color = hue((float(i) + 0.5f) / float(n));
        if (rig == Rig::SameDirection) {
            l.direction = kOblique;
        } else if (rig == Rig::Spread) {
            l.direction = -sphere[size_t(i)];
        } else {
            l.type = LightType::Point;
            l.position = vol.centre() + radius * sphere[size_t(i)];
            l.intensity = radius * radius;   // about 1 at the centre
        }
        out.push_back(l);
    }
    return out;
}

// Moves light `l` a little: a directional light turns by `degrees`, a point light goes round the
// volume's centre by that angle.
Light moved(Light l, float degrees, const Volume& vol) {
    if (l.type == LightType::Point) l.position = vol.centre() + turned(l.position - vol.centre(), degrees);
    else l.direction = glm::normalize(turned(l.direction, degrees));
    return l;
}

Scene baseScene(const Volume& vol, int resolution, bool coherent) {
    Scene s;
    s.volume().path = vol.file;
    s.volume().density = GridRef{"density", 0};
    s.render.backend = Backend::Cpu;
    s.render.width = s.render.height = 16;   // no march runs: apply() prepares every stage but it
    s.volume().material.density_scale = 2.0f;         // the reference's direct light is ~46% of the unshadowed one
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.light_resolution = resolution;
    s.effects.propagation.coherent = coherent;
    return s;
}

// One timed apply(): the "propagation" stage and what the illumination stage reported.
struct Run {
    double seconds = 1e30;   // of the propagation stage; 0 when it was kept or did not run
    bool ran = false;        // the illumination stage ran (not the case with no light on)
    LightUpdate update;
};

Run runOf(const LightRigUpdate& u) {
    Run r;
    r.seconds = 0.0;
    for (const auto& [stage, t] : u.stage_seconds)
        if (stage == "propagation") r.seconds = t;
    if (u.lighting) {
        r.ran = true;
        r.update = *u.lighting;
    }
    return r;
}

// A renderer driven by a light rig (the rig refers to the renderer: declared after it, it goes first).
struct Live {
    std::unique_ptr<Renderer> renderer;
    std::unique_ptr<LightRig> rig;
};

// The entire update of `scene`'s lights on fresh renderers, best of `repeats`; the last renderer
// is kept in `keep` if given.
Run entire(const Scene& scene, int repeats, Live* keep) {
    Run best;
    for (int r = 0; r < repeats; ++r) {
        Live live;
        live.renderer = std::make_unique<Renderer>(scene);
        live.rig = std::make_unique<LightRig>(*live.renderer, scene);
        const Run run = runOf(live.rig->apply());
        if (run.seconds < best.seconds) best = run;
        if (keep && r == repeats - 1) {
            keep->rig = std::move(live.rig);
            keep->renderer = std::move(live.renderer);
        }
    }
    return best;
}

// Least-squares slope of y against x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
    const double n = double(x.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < x.size(); ++i) sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
    const double d = n * sxx - sx * sx;
    return d > 0 ? (n * sxy - sx * sy) / d : 0.0;
}

const char* modeName(LightUpdate::Mode m) {
    return m == LightUpdate::Mode::Kept ? "kept" : m == LightUpdate::Mode::Entire ? "entire" : "selective";
}

// "selective | 2 | 1 | 175" or "(no light on: not run)"
std::string whatRan(const Run& r) {
    if (!r.ran) return "not run (no light on) | - | - | -";
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s | %d | %d | %lld", modeName(r.update.mode), r.update.sweeps, r.update.passes,
                  r.update.slices);
    return buf;
}

std::string ms(double seconds) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", 1e3 * seconds);
    return buf;
}

std::string ratio(double a, double b) {
    if (!(b > 0)) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", a / b);
    return buf;
}

// One rig at one resolution, for the summary.
struct RigResult {
    std::string rig, res;
    double per_light_seq = 0, per_light_coh = 0;
    double move8 = 0, toggle8 = 0, entire8_coh = 0, entire8_seq = 0, entire8_live = 0;
    std::string move8_mode, toggle8_mode;
    bool have8 = false;
};

RigResult measureRig(Rig rig, const Volume& vol, int resolution, const std::string& res_name, const std::vector<int>& counts,
                     int repeats) {
    std::printf("### %s, %s (light_resolution %d)\n\n", rigName(rig), res_name.c_str(), resolution);
    struct Row {
        int n;
        Run seq, coh, move, toggle, toggle_on;
        Run live_entire;   // N = 8 only
    };
    std::vector<Row> rows;
    for (int n : counts) {
        progress("%s, %s, N = %d: entire updates", rigName(rig), res_name.c_str(), n);
        Row row{n, {}, {}, {}, {}, {}, {}};
        Scene scene = baseScene(vol, resolution, false);
        scene.lights = rigLights(rig, n, vol);
        row.seq = entire(scene, repeats, nullptr);
        scene.effects.propagation.coherent = true;
        Live live;
        row.coh = entire(scene, repeats, &live);

        progress("%s, %s, N = %d: move and toggle one light", rigName(rig), res_name.c_str(), n);
        const int id = live.rig->ids().front();
        const Light original = live.rig->light(id);
        for (int r = 0; r < repeats; ++r) {
            // 3 degrees one way, then the other: every run changes one light, and every run leaves
            // it off its starting place (in the "same direction" rig: off the others' direction).
            live.rig->update(id, moved(original, r % 2 == 0 ? 3.0f : -3.0f, vol));
            const Run run = runOf(live.rig->apply());
            if (run.seconds < row.move.seconds) row.move = run;
        }
        for (int r = 0; r < repeats; ++r) {
            live.rig->toggle(id, false);
            const Run off = runOf(live.rig->apply());
            if (off.seconds < row.toggle.seconds) row.toggle = off;
            live.rig->toggle(id, true);
            const Run on = runOf(live.rig->apply());
            if (on.seconds < row.toggle_on.seconds) row.toggle_on = on;
        }
        if (n == 8) {
            // An entire update on this live renderer, into the memory it holds: flipping
            // propagation.chroma_subsampling (inert without indirect light) changes the stage's
            // settings, which it answers with an entire update. The renderer is not used after.
            progress("%s, %s, N = %d: entire update on the live renderer", rigName(rig), res_name.c_str(), n);
            Scene s = live.rig->scene();
            s.lights.front() = original;   // back where the fresh renderer had it (the moves leave it turned)
            for (int r = 0; r < repeats; ++r) {
                s.effects.propagation.chroma_subsampling = r % 2 == 0;
                live.renderer->setScene(s);
                const FrameResult f = live.renderer->prepare(std::nullopt, true);
                Run run;
                run.seconds = 0.0;
                for (const auto& [stage, t] : f.stage_seconds)
                    if (stage == "propagation") run.seconds = t;
                if (f.light_update) run.ran = true, run.update = *f.light_update;
                if (run.seconds < row.live_entire.seconds) row.live_entire = run;
            }
        }
        rows.push_back(row);
    }

    std::printf("Entire updates, fresh renderer each run, best of %d. Passes / sweeps as the illumination stage "
                "reported them (a sweep: one light along one axis; in a coherent pass, lights sharing a geometry are "
                "one tinted sweep).\n\n",
                repeats);
    std::printf("| N | sequential (ms) | passes / sweeps | coherent (ms) | passes / sweeps | coherent / sequential |\n");
    std::printf("|---|---|---|---|---|---|\n");
    std::vector<double> xs, seq, coh;
    for (const Row& r : rows) {
        std::printf("| %d | %s | %d / %d | %s | %d / %d | %s |\n", r.n, ms(r.seq.seconds).c_str(), r.seq.update.passes,
                    r.seq.update.sweeps, ms(r.coh.seconds).c_str(), r.coh.update.passes, r.coh.update.sweeps,
                    ratio(r.coh.seconds, r.seq.seconds).c_str());
        xs.push_back(r.n);
        seq.push_back(r.seq.seconds);
        coh.push_back(r.coh.seconds);
    }
    RigResult out;
    out.rig = rigName(rig);
    out.res = res_name;
    out.per_light_seq = slope(xs, seq);
    out.per_light_coh = slope(xs, coh);
    std::printf("\nPer-light cost (least-squares slope over N = %d..%d): sequential %.2f ms, coherent %.2f ms; "
                "coherent / sequential = %s (goal <= 0.1)%s.\n\n",
                counts.front(), counts.back(), 1e3 * out.per_light_seq, 1e3 * out.per_light_coh,
                ratio(out.per_light_coh, out.per_light_seq).c_str(),
                out.per_light_coh < 0 ? " (a negative slope: no cost per light measurable above the noise)" : "");

    std::printf("Edits on the coherent renderer, best of %d: move light 0 by 3 degrees (%s; to +3, -3, +3 "
                "degrees from the start), toggle it off (and back on, timed apart). Mode, sweeps, passes, slices: "
                "what the stage chose and ran; est. = its selective / entire cost estimate for the move.\n\n",
                repeats, rig == Rig::Point ? "round the volume's centre" : "its direction");
    std::printf("| N | entire (ms) | move (ms) | move / entire | mode | sweeps | passes | slices | est. | "
                "toggle off (ms) | off / entire | mode | sweeps | passes | slices | toggle on (ms) |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Row& r : rows) {
        std::printf("| %d | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.n, ms(r.coh.seconds).c_str(),
                    ms(r.move.seconds).c_str(), ratio(r.move.seconds, r.coh.seconds).c_str(), whatRan(r.move).c_str(),
                    ratio(r.move.update.selective_cost, r.move.update.entire_cost).c_str(),
                    r.toggle.ran ? ms(r.toggle.seconds).c_str() : "-",
                    r.toggle.ran ? ratio(r.toggle.seconds, r.coh.seconds).c_str() : "-", whatRan(r.toggle).c_str(),
                    r.toggle_on.ran ? ms(r.toggle_on.seconds).c_str() : "-");
        if (r.n == 8) {
            out.have8 = true;
            out.move8 = r.move.seconds;
            out.toggle8 = r.toggle.seconds;
            out.entire8_coh = r.coh.seconds;
            out.entire8_seq = r.seq.seconds;
            out.entire8_live = r.live_entire.seconds;
            out.move8_mode = modeName(r.move.update.mode);
            out.toggle8_mode = modeName(r.toggle.update.mode);
        }
    }
    std::printf("\n");
    for (const Row& r : rows)
        if (r.n == 8)
            std::printf("N = 8, an entire update on the live renderer (forced by a settings change): %s ms (%s, %d "
                        "sweeps, %d passes); move / that = %s, toggle off / that = %s.\n",
                        ms(r.live_entire.seconds).c_str(), modeName(r.live_entire.update.mode), r.live_entire.update.sweeps,
                        r.live_entire.update.passes, ratio(r.move.seconds, r.live_entire.seconds).c_str(),
                        r.toggle.ran ? ratio(r.toggle.seconds, r.live_entire.seconds).c_str() : "-");
    for (const Row& r : rows)
        if (r.n == 8 || r.n == counts.back())
            std::printf("N = %d: move: %s; toggle off: %s.\n", r.n, r.move.update.reason.c_str(),
                        r.toggle.ran ? r.toggle.update.reason.c_str() : "not run");
    std::printf("\n");
    return out;
}

// ---------------------------------------------------------------------------------------------
// Calibration of the cost estimate (SweepCost in src/lighting/propagation/propagation_stages.h, in units of one
// directional direct sweep).

void calibration(const Volume& vol, int resolution, int repeats) {
    std::printf("## Calibration of the cost estimate, 1x (light_resolution %d), entire updates, best of %d\n\n",
                resolution, repeats);
    // The grid's dimensions: an axis-aligned light walks dims[axis] slices in its one pass.
    glm::ivec3 dims(0);
    double axis_seconds[3] = {0, 0, 0};
    for (int axis = 0; axis < 3; ++axis) {
        progress("calibration: light along -%c", "xyz"[axis]);
        Scene s = baseScene(vol, resolution, true);
        Light l;
        l.direction = glm::vec3(0.0f);
        l.direction[axis] = -1.0f;
        s.lights = {l};
        const Run r = entire(s, repeats, nullptr);
        dims[axis] = int(r.update.slices);
        axis_seconds[axis] = r.seconds;
    }
    const double cells = double(dims.x) * dims.y * dims.z;
    auto ns = [&](double seconds) { return 1e9 * seconds / cells; };
    std::printf("Illumination volume %d x %d x %d = %.2f M cells. Times are the \"propagation\" stage of an entire "
                "update (zeroing the volume, then the passes), per cell of the volume.\n\n",
                dims.x, dims.y, dims.z, cells / 1e6);

    // K directional lights of slightly different directions (all principal axis -y), in one
    // coherent pass and in K sequential passes: the coherent slope is a further light's sweep, the
    // difference of the slopes a pass's own cost, and what is left of the coherent intercept the
    // update's fixed cost (allocating and zeroing the volume on a fresh renderer).
    const glm::vec3 e1 = glm::normalize(glm::cross(kOblique, glm::vec3(1.0f, 0.0f, 0.0f)));
    const glm::vec3 e2 = glm::cross(kOblique, e1);
    std::vector<double> ks, coh, seq;
    std::printf("| case | passes / sweeps | ms | ns/cell |\n|---|---|---|---|\n");
    for (int axis = 0; axis < 3; ++axis)
        std::printf("| 1 directional light along -%c | 1 / 1 | %s | %.2f |\n", "xyz"[axis], ms(axis_seconds[axis]).c_str(),
                    ns(axis_seconds[axis]));
    double one_light = 0;
    for (int k : {1, 2, 4, 8, 16}) {
        progress("calibration: %d directional lights, one coherent pass and %d sequential", k, k);
        Scene s = baseScene(vol, resolution, true);
        for (int i = 0; i < k; ++i) {
            Light l;
            const float a = 6.2831853f * float(i) / float(k);
            l.direction = i == 0 ? kOblique : glm::normalize(kOblique + 0.06f * (std::cos(a) * e1 + std::sin(a) * e2));
            l.color = hue((float(i) + 0.5f) / float(k));
            s.lights.push_back(l);
        }
        const Run c = entire(s, repeats, nullptr);
        s.effects.propagation.coherent = false;
        const Run q = entire(s, repeats, nullptr);
        if (k == 1) one_light = c.seconds;
        ks.push_back(k);
        coh.push_back(c.seconds);
        seq.push_back(q.seconds);
        for (const Run* r : {&c, &q})
            std::printf("| %d directional light%s, oblique, directions within 3.4 deg, %s | %d / %d | %s | %.2f |\n", k,
                        k == 1 ? "" : "s", r == &c ? "coherent" : "sequential", r->update.passes, r->update.sweeps,
                        ms(r->seconds).c_str(), ns(r->seconds));
    }
    const double sweep = slope(ks, coh), per_pass = slope(ks, seq) - sweep;

    // The same one-light update on a live renderer: two lights along the oblique direction, one
    // toggled off and on. Either way one sweep is left (the twins merge), so the stage re-runs
    // the whole volume (an entire update) into the memory it already holds.
    progress("calibration: one light, entire update on a live renderer");
    Run warm;
    {
        Scene s = baseScene(vol, resolution, true);
        Light l;
        l.direction = kOblique;
        s.lights = {l, l};
        s.lights[1].color = glm::vec3(0.2f, 0.4f, 1.0f);
        Live live;
        entire(s, 1, &live);
        const int id = live.rig->ids().back();
        for (int r = 0; r < repeats; ++r) {
            live.rig->toggle(id, r % 2 != 0);
            const Run run = runOf(live.rig->apply());
            if (run.seconds < warm.seconds) warm = run;
        }
        std::printf("| 1 directional light, oblique, on a live renderer (a twin toggled) | %d / %d | %s (%s) | %.2f |\n",
                    warm.update.passes, warm.update.sweeps, ms(warm.seconds).c_str(), modeName(warm.update.mode),
                    ns(warm.seconds));
    }
    const double fixed = one_light - warm.seconds;   // what a fresh renderer adds: allocating the volume

    // A point light straight above the volume's centre, far enough that one -y sweep covers it.
    progress("calibration: one point light, one sweep");
    Scene sp = baseScene(vol, resolution, true);
    Light point;
    point.type = LightType::Point;
    const float height = 0.5f * (vol.hi.y - vol.lo.y) + 1.2f * glm::length(vol.hi - vol.lo);
    point.position = vol.centre() + glm::vec3(0.0f, height, 0.0f);
    point.intensity = height * height;
    sp.lights = {point};
    const Run p = entire(sp, repeats, nullptr);
    std::printf("| 1 point light above the volume | %d / %d | %s | %.2f |\n", p.update.passes, p.update.sweeps,
                ms(p.seconds).c_str(), ns(p.seconds));

    // The oblique light with indirect light on (defaults: 9 taps, 30 deg cone).
    progress("calibration: one directional light with indirect light");
    Scene si = baseScene(vol, resolution, true);
    Light key;
    key.direction = kOblique;
    si.lights = {key};
    si.effects.indirect = Indirect{};
    const Run ind = entire(si, repeats, nullptr);
    std::printf("| 1 directional light, oblique, indirect light on (9 taps) | %d / %d | %s | %.2f |\n\n", ind.update.passes,
                ind.update.sweeps, ms(ind.seconds).c_str(), ns(ind.seconds));

    std::printf("Fits over K = 1..16 lights (least squares): a further directional light in a coherent pass %.2f "
                "ns/cell (one sweep); a further pass (sequential slope - coherent slope) %.2f ns/cell. A fresh "
                "renderer's update costs %.2f ns/cell more than a live one's (allocating the volume: the one-light "
                "rows, fresh against live).\n\n",
                ns(sweep), ns(per_pass), ns(fixed));
    std::printf("| in units of a directional sweep (%.2f ns/cell) | measured | estimate's constant |\n|---|---|---|\n",
                ns(sweep));
    std::printf("| a further pass (its own cost) | %.2f | SweepCost::kPass = %g |\n", per_pass / sweep, SweepCost::kPass);
    std::printf("| one-light update on a live renderer (pass + sweep) | %.2f | kPass + 1 = %g |\n", warm.seconds / sweep,
                SweepCost::kPass + 1.0);
    std::printf("| allocating the volume (fresh renderer only) | %.2f | 0 (not modelled) |\n", fixed / sweep);
    std::printf("| point-light sweep (1 + (point stage - one-light stage) / sweep) | %.2f | kPointSweep = %g |\n",
                1.0 + (p.seconds - one_light) / sweep, SweepCost::kPointSweep);
    std::printf("| indirect pass ((stage with indirect - without) / sweep) | %.2f | kPass + kIndirect = %g |\n",
                (ind.seconds - one_light) / sweep, SweepCost::kPass + SweepCost::kIndirect);
    std::printf("| x sweep / y sweep (axis lights, whole stages) | %.2f | kXAxis = %g |\n\n",
                axis_seconds[1] > 0 ? axis_seconds[0] / axis_seconds[1] : 0.0, SweepCost::kXAxis);
}

}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);   // tables show as they come when redirected
    bench::Options options;
    if (!bench::parseOptions(argc, argv, "voxlux_bench_multilight", bench::sourceDir() + "/../shared/data",
                             options))
        return 2;
    const bool quick = options.quick;
    const std::string file = options.data + "/arnold-usd/smoke.vdb";
    if (!std::filesystem::exists(file)) {
        std::printf("%s absent: nothing to measure\n", file.c_str());
        return 1;
    }
    const Volume vol = measureVolume(file);
    const int full = vol.longest, quarter = std::max(4, (vol.longest + 2) / 4);
    const int repeats = quick ? 1 : 3;
    const std::vector<int> counts = quick ? std::vector<int>{1, 2, 8} : std::vector<int>{1, 2, 4, 8, 16, 40};
    const std::vector<int> point_counts = quick ? std::vector<int>{1, 2, 8} : std::vector<int>{1, 2, 4, 8};

    std::printf("# Many lights: coherent passes and selective updates (CPU backend, %u threads)\n\n",
                std::thread::hardware_concurrency());
    if (quick) std::printf("(--quick: one run per figure and fewer light counts; a smoke test, not figures to quote)\n\n");
    std::printf("%s (grid density), density_scale 2, active voxels' longest side %d voxels; world box (%.1f, %.1f, %.1f) "
                "to (%.1f, %.1f, %.1f). Shadows propagation, direct light only, blend_axes off.\n"
                "Resolutions: 1x = light_resolution %d; 1/4 = %d (a quarter per axis, 1/64 of the cells).\n\n",
                file.c_str(), vol.longest, vol.lo.x, vol.lo.y, vol.lo.z, vol.hi.x, vol.hi.y, vol.hi.z, full, quarter);

    std::vector<RigResult> results;
    for (const auto& [res, name] : {std::pair<int, std::string>{full, "1x"}, {quarter, "1/4"}}) {
        std::printf("## %s: light_resolution %d\n\n", name.c_str(), res);
        results.push_back(measureRig(Rig::SameDirection, vol, res, name, counts, repeats));
        results.push_back(measureRig(Rig::Spread, vol, res, name, counts, repeats));
        // The point rig at 1x costs seconds per update: best of 2 there keeps the run under 4
        // minutes on a busy machine, and --quick leaves it out.
        if (res == full && quick) {
            std::printf("### point, 1x: left out with --quick\n\n");
            continue;
        }
        results.push_back(measureRig(Rig::Point, vol, res, name, point_counts, res == full ? std::min(repeats, 2) : repeats));
    }

    std::printf("## Summary against the goals\n\n");
    std::printf("Per light: least-squares slope of the entire update's time against N. 8 lights: entire updates "
                "coherent, on a fresh renderer (as in the tables) and on the live one (forced by a settings change, "
                "no allocation); the move and toggle-off times are on the live renderer.\n\n");
    std::printf("| rig | res | per light, sequential (ms) | per light, coherent (ms) | coherent / sequential (goal <= 0.1) | "
                "8 lights: entire, fresh (ms) | entire, live (ms) | move one (ms) | move / entire fresh (goal <= 0.25) | "
                "move / entire live | chosen | toggle off (ms) | off / entire fresh | off / entire live | chosen |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const RigResult& r : results) {
        auto cell = [&](const std::string& text) { return r.have8 ? text : std::string("-"); };
        std::printf("| %s | %s | %.2f | %.2f | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.rig.c_str(),
                    r.res.c_str(), 1e3 * r.per_light_seq, 1e3 * r.per_light_coh,
                    ratio(r.per_light_coh, r.per_light_seq).c_str(), cell(ms(r.entire8_coh)).c_str(),
                    cell(ms(r.entire8_live)).c_str(), cell(ms(r.move8)).c_str(), cell(ratio(r.move8, r.entire8_coh)).c_str(),
                    cell(ratio(r.move8, r.entire8_live)).c_str(), cell(r.move8_mode).c_str(), cell(ms(r.toggle8)).c_str(),
                    cell(ratio(r.toggle8, r.entire8_coh)).c_str(), cell(ratio(r.toggle8, r.entire8_live)).c_str(),
                    cell(r.toggle8_mode).c_str());
    }
    std::printf("\n");

    calibration(vol, full, repeats);
    std::printf("Total run time %.0f s.\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - kStart).count());
    return 0;
}
