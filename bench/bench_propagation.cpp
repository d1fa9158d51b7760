// What the illumination-volume propagation costs and how accurate it is
// (docs/accuracy-propagation.md).
//
// 1. The paper's GTX 285 figures (Ropinski et al. 2010) against the CPU backend on a full 256^3
//    illumination volume: the "propagation" stage through the Renderer for axis-aligned and
//    diagonal lights (the diagonal on one axis, the default, and with blend_axes), per sweep
//    against a STREAM-style copy measured here, and a 1024x1024 march that reads the volume
//    without regenerating it.
// 2. On real caches, sweeps of each knob (illumination resolution on one axis, the default; axis
//    blending on against off; blur taps, chroma subsampling, eye pass): the time of every pass and
//    the image's error against a ray-marched reference.
// Prints figures and writes an error-against-time plot; it asserts nothing.
//
//   build/voxlux_bench_propagation [--data DIR] [--svg docs/accuracy-propagation.svg] [--quick]
//                                  [--paper-only | --sweeps-only]
#include <openvdb/tools/Dense.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include "source_dir.h"
#include "bench_timing.h"
#include "scene/camera.h"
#include "lighting/propagation/light_sweeps.h"
#include "render/renderer.h"
#include "volume/volume_stages.h"
#include "tools/svg_plot.h"
#include "volume/vdb_loader.h"

namespace {

using namespace voxlux;

using bench::copyBandwidth;

// ---------------------------------------------------------------------------------------------
// Part 1: against the paper.

// Smooth value noise: hashed lattice values every `period` cells, smoothstep-interpolated.
float valueNoise(glm::vec3 p, float period, uint32_t seed) {
    const glm::vec3 q = p / period, f = glm::floor(q), t = q - f;
    const glm::vec3 s = t * t * (3.0f - 2.0f * t);
    auto lattice = [&](int x, int y, int z) {
        uint32_t h = seed ^ (uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u);
        h ^= h >> 15, h *= 0x2c1b3c6du, h ^= h >> 12, h *= 0x297a2d39u, h ^= h >> 15;
        return float(h & 0xffffff) / float(0xffffff);
    };
    const glm::ivec3 c(f);
    float v[2][2][2];
    for (int k = 0; k < 8; ++k) v[k >> 2][(k >> 1) & 1][k & 1] = lattice(c.x + (k & 1), c.y + ((k >> 1) & 1), c.z + (k >> 2));
    auto lerp = [](float a, float b, float w) { return a + (b - a) * w; };
    const float y0 = lerp(lerp(v[0][0][0], v[0][0][1], s.x), lerp(v[0][1][0], v[0][1][1], s.x), s.y);
    const float y1 = lerp(lerp(v[1][0][0], v[1][0][1], s.x), lerp(v[1][1][0], v[1][1][1], s.x), s.y);
    return lerp(y0, y1, s.z);
}

// n^3 cells of a positive smooth fog with mean about 1 (two octaves, 32 and 11 cells), x fastest.
std::vector<float> noiseField(int n) {
    std::vector<float> out(size_t(n) * n * n);
    tbb::parallel_for(0, n, [&](int z) {
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec3 p(x, y, z);
                out[(size_t(z) * n + y) * n + x] =
                    0.1f + 1.8f * (0.65f * valueNoise(p, 32.0f, 1u) + 0.35f * valueNoise(p, 11.0f, 2u));
            }
    });
    return out;
}

// Optical depth of the synthetic fog across the cube (mean field 1, whatever its size): light and camera rays
// cross it attenuated but not extinguished.
constexpr float kSyntheticDepth = 4.0f;

// Writes the n^3 noise field as a fog VDB (grid "density", one world unit per voxel) to a new file
// in the temp directory; returns its path.
std::string writeNoiseVdb(int n) {
    const std::vector<float> field = noiseField(n);
    initOpenVdb();
    auto grid = openvdb::FloatGrid::create(0.0f);
    {
        openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(
            openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(n - 1)));
        // LayoutXYZ: z fastest.
        tbb::parallel_for(0, n, [&](int x) {
            for (int y = 0; y < n; ++y)
                for (int z = 0; z < n; ++z) dense.data()[(size_t(x) * n + y) * n + z] = field[(size_t(z) * n + y) * n + x];
        });
        openvdb::tools::copyFromDense(dense, *grid, 0.0f);
    }
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("voxlux-bench-propagation-" + std::to_string(::getpid()) + ".vdb"))
                                 .string();
    openvdb::io::File(path).write({grid});
    return path;
}

// Renders `scene` on `r` with the light's intensity nudged by `nudge` (a new lights key, so the
// propagation reruns; light grid, bricks and load are kept).
FrameResult renderNudged(Renderer& r, Scene scene, float nudge) {
    scene.lights[0].intensity *= 1.0f + nudge;
    r.setScene(scene);
    return r.render(std::nullopt, false);
}

double stage(const FrameResult& f, const std::string& name) {
    for (const auto& [stage, t] : f.stage_seconds)
        if (stage == name) return t;
    return 0.0;
}

bool wasReused(const FrameResult& f, const std::string& name) {
    return std::find(f.reused.begin(), f.reused.end(), name) != f.reused.end();
}

size_t nonFinitePixels(const FrameResult& f) {
    size_t bad = 0;
    for (const auto& p : f.image.pixels)
        for (int c = 0; c < 4; ++c) bad += !std::isfinite(p.rgba[c]);
    return bad;
}

// "+x 0.50, -y 0.50"
std::string sweepList(const std::vector<Sweep>& sweeps) {
    std::string out;
    for (const Sweep& s : sweeps) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%s%c%c %.2f", out.empty() ? "" : ", ", s.sign > 0 ? '+' : '-', "xyz"[s.axis],
                      s.weight);
        out += buf;
    }
    return out;
}

// Bytes a sweep moves at least, per cell: the extinction grid read once (4 B) and the volume's
// RGB block read and written once (3 floats, direct and indirect alike). x sweeps move more: they
// run on a slice-major copy of the extinction (made once per grid, then kept) and write their
// result to a slice-major buffer that is added back (write + read): 52 B.
constexpr double kSweepBytes = 4.0 + 2.0 * 12.0;

void paperComparison(bool quick) {
    const int n = quick ? 128 : 256, repeats = quick ? 1 : 2;
    const size_t cells = size_t(n) * n * n;
    std::printf("## Against Ropinski et al. 2010 (GTX 285), full %d^3 illumination volume, CPU backend, %u threads\n\n",
                n, std::thread::hardware_concurrency());
    if (quick) std::printf("(--quick: %d^3 and a 512^2 frame; not the figures to compare with the paper)\n\n", n);
    const double copy = copyBandwidth();
    std::printf("STREAM-style copy bandwidth (same binary): %.1f GB/s\n\n", copy / 1e9);

    const std::string path = writeNoiseVdb(n);
    Scene scene;
    scene.volume().path = path;
    scene.render.backend = Backend::Cpu;
    scene.render.width = scene.render.height = 16;   // the march is not what is timed here
    scene.volume().material.density_scale = kSyntheticDepth / float(n);
    scene.effects.shadows = ShadowMethod::Propagation;
    scene.effects.light_resolution = n;
    Light key;
    key.intensity = 6.0f;
    scene.lights = {key};
    const Indirect in;   // the defaults: 9 taps, 30 degree cone, Phong 4, the diffusion model (one sweep, as Kniss's)

    Renderer renderer(scene);
    const FrameResult first = renderer.render(std::nullopt, false);
    for (const std::string& w : first.warnings) std::printf("WARNING: %s\n", w.c_str());
    std::printf("The fog written as a %d^3 VDB and rendered through the Renderer at light_resolution %d, %dx%d "
                "pixels (load %.2f s, brick %.2f s, light_grid %.2f s, once). Each row: the \"propagation\" stage "
                "(zeroing the volume, then every sweep), best of %d, the light's intensity nudged so that only the "
                "propagation reruns. blend_axes as in its column (off is the default; an axis-aligned light has "
                "one sweep either way).\nBytes per sweep and cell, at least: %.0f (extinction read 4, RGB volume "
                "read + write 12 + 12), direct and indirect alike.\nThe stage with indirect light runs the direct "
                "sweeps as well: its indirect sweep is (stage - direct-only stage) / sweeps.\n\n",
                n, n, scene.render.width, scene.render.height, stage(first, "load"), stage(first, "brick"),
                stage(first, "light_grid") + stage(first, "illumination_grid"), repeats, kSweepBytes);

    struct PaperLight {
        const char* name;
        glm::vec3 dir;
        bool blend;
    };
    const glm::vec3 diagonal = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));
    // The defaults (blend_axes off) first; then the diagonal blended, as in the paper.
    const std::vector<PaperLight> lights = {{"axis (-1,0,0)", {-1.0f, 0.0f, 0.0f}, false},
                                            {"axis (0,-1,0)", {0.0f, -1.0f, 0.0f}, false},
                                            {"axis (0,0,-1)", {0.0f, 0.0f, -1.0f}, false},
                                            {"diagonal (1,-1,0)", diagonal, false},
                                            {"diagonal (1,-1,0)", diagonal, true}};
    const size_t kDiagonalOneAxis = 3, kDiagonalBlended = 4;
    auto blendName = [](bool blend) { return blend ? "on" : "off (default)"; };
    auto sceneFor = [&](const PaperLight& l, bool indirect) {
        Scene s = scene;
        s.lights[0].direction = l.dir;
        s.effects.propagation.blend_axes = l.blend;
        if (indirect) s.effects.indirect = in;
        return s;
    };
    float nudge = 0.0f;
    // Best of `repeats` propagation stages; `sweeps`, if given, gets how many sweeps the stage ran.
    auto propagation = [&](const Scene& s, int* sweeps = nullptr) {
        double t = 1e30;
        for (int run = 0; run < repeats; ++run) {
            const FrameResult f = renderNudged(renderer, s, nudge += 1e-4f);
            if (sweeps && f.light_update) *sweeps = f.light_update->sweeps;
            if (wasReused(f, "propagation")) std::printf("WARNING: propagation reused, not timed\n");
            if (!wasReused(f, "light_grid") || !wasReused(f, "illumination_grid")) std::printf("WARNING: light grid rebuilt\n");
            if (const size_t bad = nonFinitePixels(f)) std::printf("WARNING: %zu non-finite pixel channels\n", bad);
            t = std::min(t, stage(f, "propagation"));
        }
        return t;
    };

    std::printf("| light | blend_axes | sweeps (axis, weight) | indirect | propagation stage (s) | per sweep (s) | "
                "ns/cell | B/cell | GB/s | of copy bw |\n|---|---|---|---|---|---|---|---|---|---|\n");
    std::vector<double> with_indirect(lights.size(), 0.0);   // the stage with 9 taps, per light
    double y_sweep[2] = {0.0, 0.0};                           // the -y light's direct and indirect sweep
    for (size_t li = 0; li < lights.size(); ++li) {
        const PaperLight& l = lights[li];
        // The grid's cells are cubes, so the light's direction in grid space is its world direction.
        const std::vector<Sweep> sweeps = sweepsFor(l.dir, l.blend);
        const double k = double(sweeps.size());
        const double direct = propagation(sceneFor(l, false));
        const double both = propagation(sceneFor(l, true));
        auto row = [&](const char* indirect, double stage_s, double per_sweep, double bytes) {
            std::printf("| %s | %s | %s | %s | %.3f | %.3f | %.1f | %.0f | %.2f | %.1f%% |\n", l.name,
                        blendName(l.blend), sweepList(sweeps).c_str(), indirect, stage_s, per_sweep, per_sweep / double(cells) * 1e9, bytes,
                        bytes * double(cells) / per_sweep / 1e9, 100.0 * bytes * double(cells) / per_sweep / copy);
        };
        row("none", direct, direct / k, kSweepBytes);
        row("9 taps", both, (both - direct) / k, kSweepBytes);
        with_indirect[li] = both;
        if (li == 1) {   // the -y light: what a point light's sweep is compared with below
            y_sweep[0] = direct;
            y_sweep[1] = both - direct;
        }
    }
    std::printf("\n");

    // Point lights: each cell reads the previous slice where its own ray from the light crosses it,
    // and weighs its value by its own flow. Far above the volume one -y sweep carries the light (the
    // volume's slopes stay under 0.25); just outside a corner of the box several sweeps do, each
    // over the cells within slope 3 of the light.
    const glm::vec3 centre(0.5f * float(n));
    const float far = 0.5f * float(n) + 1.2f * std::sqrt(3.0f) * float(n), near = 1.05f * 0.5f * std::sqrt(3.0f) * float(n);
    const struct {
        const char* name;
        glm::vec3 position;
    } points[] = {{"above, 1.2 diagonals over the top", centre + glm::vec3(0.0f, far, 0.0f)},
                  {"just outside a corner of the box", centre + near * glm::normalize(glm::vec3(0.6f, 1.0f, 0.45f))}};
    std::printf("Point lights, the same stage; per sweep against the -y light's sweep above (direct: its stage; "
                "indirect: its stage with 9 taps less without).\n\n");
    std::printf("| point light | sweeps | indirect | propagation stage (s) | per sweep (s) | per sweep / -y sweep |\n"
                "|---|---|---|---|---|---|\n");
    for (const auto& point : points) {
        Scene s = sceneFor(lights[1], false);
        s.lights[0].type = LightType::Point;
        s.lights[0].position = point.position;
        s.lights[0].intensity = key.intensity * glm::dot(point.position - centre, point.position - centre);
        int sweeps = 0;
        const double direct = propagation(s, &sweeps);
        s.effects.indirect = in;
        const double both = propagation(s);
        const double k = std::max(sweeps, 1);
        std::printf("| %s | %d | none | %.3f | %.3f | %.2f |\n", point.name, sweeps, direct, direct / k, direct / k / y_sweep[0]);
        std::printf("| %s | %d | 9 taps | %.3f | %.3f | %.2f |\n", point.name, sweeps, both, (both - direct) / k,
                    (both - direct) / k / y_sweep[1]);
    }
    std::printf("\n");

    // A big frame marching the diagonal light's volume without regenerating it: the same lights
    // key as a 16x16 render just before, so the stage is reused. The march reads the volume the
    // same way whatever sweeps filled it, so one light serves both blend settings.
    const int size = quick ? 512 : 1024;
    const PaperLight& marched = lights[kDiagonalOneAxis];
    std::printf("A %dx%d frame at march step 0.5 voxel reading the diagonal light's volume without regenerating it "
                "(propagation reused), one run each.\n\n",
                size, size);
    std::printf("| light | blend_axes | indirect | %dx%d march (s) | samples/pixel | march ns/sample/thread |\n"
                "|---|---|---|---|---|---|\n",
                size, size);
    double diagonal_march = 0;
    for (int indirect : {0, 1}) {
        Scene s = sceneFor(marched, indirect);
        nudge += 1e-4f;
        renderNudged(renderer, s, nudge);
        s.render.width = s.render.height = size;
        s.render.step = 0.5f;
        const FrameResult big = renderNudged(renderer, s, nudge);
        double samples = 0;
        for (const auto& p : big.image.pixels) samples += p.samples;
        const double t = stage(big, "march");
        std::printf("| %s | %s | %s | %.3f%s | %.0f | %.0f |\n", marched.name, blendName(marched.blend),
                    indirect ? "9 taps" : "none", t,
                    wasReused(big, "propagation") ? "" : " (propagation NOT reused)",
                    samples / double(big.image.pixels.size()),
                    t / samples * 1e9 * std::thread::hardware_concurrency());
        if (const size_t bad = nonFinitePixels(big)) std::printf("|  WARNING: %zu non-finite pixel channels | | | | | |\n", bad);
        if (indirect) diagonal_march = t;
    }
    std::filesystem::remove(path);

    // The paper: the 360x270x550 mouse at 1024^2 on a GTX 285, 7.2 fps regenerating the volume every
    // frame and 16.5 fps without; the difference is what regeneration costs there.
    const double paper_cells = 360.0 * 270.0 * 550.0;
    const double paper_regen = 1.0 / 7.2 - 1.0 / 16.5;
    const double blended = with_indirect[kDiagonalBlended], one_axis = with_indirect[kDiagonalOneAxis];
    std::printf("\nThe paper blends two axes (blend_axes on); voxlux's default sweeps one. Diagonal light, 9 taps, "
                "%d^3 volume, %dx%d frame.\n\n",
                n, size, size);
    std::printf("| | paper: GTX 285, mouse 360x270x550, 1024x1024 | voxlux, blend_axes on (as the paper) | paper / voxlux "
                "| voxlux, blend_axes off (default) | paper / voxlux |\n|---|---|---|---|---|---|\n");
    auto ratioRow = [](const char* what, const char* paper_text, double paper, double a, double b, const char* unit,
                       double scale) {
        std::printf("| %s | %s | %.*f %s | %.4fx | %.*f %s | %.4fx |\n", what, paper_text, scale > 1 ? 1 : 3, a * scale,
                    unit, paper / a, scale > 1 ? 1 : 3, b * scale, unit, paper / b);
    };
    ratioRow("frame without regeneration", "0.061 s (16.5 fps)", 1.0 / 16.5, diagonal_march, diagonal_march, "s", 1);
    ratioRow("frame with regeneration", "0.139 s (7.2 fps)", 1.0 / 7.2, blended + diagonal_march,
             one_axis + diagonal_march, "s", 1);
    char regen[64], per_cell[64];
    std::snprintf(regen, sizeof regen, "%.3f s", paper_regen);
    std::snprintf(per_cell, sizeof per_cell, "%.2f ns (if at the data's resolution)", paper_regen / paper_cells * 1e9);
    ratioRow("regeneration (the difference)", regen, paper_regen, blended, one_axis, "s", 1);
    ratioRow("regeneration per cell", per_cell, paper_regen / paper_cells, blended / double(cells),
             one_axis / double(cells), "ns", 1e9);
    std::printf("\n");
}

// ---------------------------------------------------------------------------------------------
// Part 2: sweeps on real caches.

struct Render {
    double light_grid = 0, propagation = 0, march = 0;
    RenderImage image;
    double total() const { return light_grid + propagation + march; }
};

// `scene`, best of `runs` renders on fresh renderers.
Render render(const Scene& scene, int runs) {
    bench::TimedRender t = bench::renderFresh(scene, runs);
    // The eye sweep is its own stage (a camera move re-runs it alone); here it counts as propagation.
    return {t("light_grid") + t("illumination_grid"), t("propagation") + t("eye_pass"), t("march"), std::move(t.image)};
}

// Over the reference's footprint (pixels with alpha > 0.01), on the three channels of one AOV:
// RMSE divided by the reference's mean, and the relative bias (mean / reference mean - 1).
struct Error {
    double rel_rmse = 0, bias = 0;
    size_t non_finite = 0;
};

Error aovError(const RenderImage& a, const RenderImage& ref, glm::vec3 kernel::VxPixel::*aov) {
    Error e;
    double sq = 0, sum = 0, sum_ref = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        for (int c = 0; c < 4; ++c) e.non_finite += !std::isfinite(a.pixels[i].rgba[c]);
        if (ref.pixels[i].rgba.w <= 0.01f) continue;
        for (int c = 0; c < 3; ++c) {
            const double x = (a.pixels[i].*aov)[c], r = (ref.pixels[i].*aov)[c];
            if (!std::isfinite(x)) ++e.non_finite;
            sq += (x - r) * (x - r);
            sum += x;
            sum_ref += r;
            ++n;
        }
    }
    const double mean_ref = n ? sum_ref / double(n) : 0.0;
    e.rel_rmse = mean_ref > 0 ? std::sqrt(sq / double(n)) / mean_ref : 0.0;
    e.bias = sum_ref > 0 ? sum / sum_ref - 1.0 : 0.0;
    return e;
}

double meanAov(const RenderImage& img, const RenderImage& ref, glm::vec3 kernel::VxPixel::*aov) {
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < img.pixels.size(); ++i)
        if (ref.pixels[i].rgba.w > 0.01f) sum += (img.pixels[i].*aov)[0] + (img.pixels[i].*aov)[1] + (img.pixels[i].*aov)[2], n += 3;
    return n ? sum / double(n) : 0.0;
}

struct Dataset {
    std::string name, file, grid;
    bool z_up;
    float density_scale;
};

std::string errorCell(const Error& e) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.4f | %+.4f", e.rel_rmse, e.bias);
    std::string s = buf;
    if (e.non_finite) s += " (" + std::to_string(e.non_finite) + " NON-FINITE)";
    return s;
}

// One blend_axes on/off pair for the summary table.
struct BlendPair {
    std::string cache, res;
    Error on, off;
    double prop_on = 0, prop_off = 0;
};

void sweep(const Dataset& d, bool quick, std::vector<PlotSeries>& plot, const char* color,
           std::vector<BlendPair>& blends) {
    const int runs = quick ? 1 : 2;
    Scene base;
    base.volume().path = d.file;
    base.volume().density = GridRef{d.grid, 0};
    base.render.width = 320;
    base.render.height = 240;
    base.render.backend = Backend::Cpu;
    base.volume().material.density_scale = d.density_scale;

    // A fixed camera: the default three-quarter framing, turned to Z up for the Blender cache.
    const LoadedVolume volume = loadVolume(d.file, base.volume());
    Camera cam = frameActiveVoxels(volume, base);
    Light key;
    key.intensity = 6.0f;
    if (d.z_up) {
        const float dist = glm::length(cam.position - cam.look_at);
        cam.position = cam.look_at + dist * glm::normalize(glm::vec3(0.55f, -1.0f, 0.3f));
        cam.up = glm::vec3(0.0f, 0.0f, 1.0f);
        key.direction = glm::normalize(glm::vec3(-0.6f, -0.3f, -0.7f));
    } else {
        key.direction = glm::normalize(glm::vec3(-0.6f, -0.7f, -0.3f));
    }
    base.camera = cam;
    base.lights = {key};
    const openvdb::CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    const int longest = std::max({box.dim().x(), box.dim().y(), box.dim().z()});

    Scene reference = base;
    reference.effects.shadows = ShadowMethod::Raymarch;
    reference.render.shadow_step = 0.5f;
    const Render ref = render(reference, runs);
    Scene unshadowed = base;
    unshadowed.effects.shadows = ShadowMethod::None;
    const Render open = render(unshadowed, 1);
    const Error open_error = aovError(open.image, ref.image, &kernel::VxPixel::direct);

    std::printf("## %s (%s, grid %s), %dx%d\n\n", d.name.c_str(), d.file.c_str(), d.grid.c_str(), base.render.width,
                base.render.height);
    std::printf("Active voxels' longest side %d voxels; density_scale %g; the reference's direct light is %.0f%% of "
                "the unshadowed one.\n",
                longest, d.density_scale,
                100.0 * meanAov(ref.image, ref.image, &kernel::VxPixel::direct) /
                    meanAov(open.image, ref.image, &kernel::VxPixel::direct));
    std::printf("Reference: ray-marched shadows (shadow step 0.5 voxel), march %.3f s. Without shadows: march %.3f s, "
                "relative RMSE %.4f, bias %+.4f.\n\n",
                ref.march, open.march, open_error.rel_rmse, open_error.bias);

    // Direct light against the reference: the illumination resolution on one axis (the default),
    // then blend_axes on at 1/2 and 1x.
    std::printf("| light res | blend_axes | light_grid (s) | propagation (s) | march (s) | total (s) | rel. RMSE | bias |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    PlotSeries by_res{d.name + ": res 1/4, 1/2, 1x" + (quick ? "" : ", 2x") + ", one axis", color, {}};
    PlotSeries blended{d.name + ": res 1/2, 1x, blend_axes on (unlabelled)", color, {}};
    blended.dashed = true;
    struct Point {
        Error e;
        double propagation;
    };
    auto point = [&](int res, bool blend, PlotSeries& series, int n_runs) {
        Scene s = base;
        s.effects.shadows = ShadowMethod::Propagation;
        s.effects.light_resolution = res;
        s.effects.propagation.blend_axes = blend;
        const Render r = render(s, n_runs);
        const Error e = aovError(r.image, ref.image, &kernel::VxPixel::direct);
        std::printf("| %d | %s | %.3f | %.3f | %.3f | %.3f | %s |\n", res, blend ? "on" : "off (default)", r.light_grid,
                    r.propagation, r.march, r.total(), errorCell(e).c_str());
        // The blended points sit beside the one-axis ones at the same resolution: labelled once.
        series.points.push_back({r.total(), e.rel_rmse, blend ? "" : std::to_string(res)});
        return Point{e, r.propagation};
    };
    const int quarter = std::max(4, (longest + 2) / 4), half = std::max(4, (longest + 1) / 2);
    point(quarter, false, by_res, runs);
    const Point half_off = point(half, false, by_res, runs);
    const Point full_off = point(longest, false, by_res, runs);
    if (!quick) point(2 * longest, false, by_res, 1);   // one run: the slowest point
    const Point half_on = point(half, true, blended, runs);
    const Point full_on = point(longest, true, blended, runs);
    std::printf("\n");
    plot.push_back(by_res);
    plot.push_back(blended);
    blends.push_back({d.name, std::to_string(half) + " (1/2)", half_on.e, half_off.e, half_on.propagation,
                      half_off.propagation});
    blends.push_back({d.name, std::to_string(longest) + " (1x)", full_on.e, full_off.e, full_on.propagation,
                      full_off.propagation});

    // Indirect light: no ray-marched counterpart, so each knob is compared with its own best
    // setting on the indirect AOV; times are what matters.
    const int res = half;
    Scene lit = base;
    lit.effects.shadows = ShadowMethod::Propagation;
    lit.effects.light_resolution = res;
    lit.effects.indirect = Indirect{};   // the defaults: 30 degree cone, Phong 4, transport colour 0.6
    auto indirectRender = [&](int samples, bool chroma, bool eye) {
        Scene s = lit;
        s.effects.indirect->samples = samples;
        s.effects.propagation.chroma_subsampling = chroma;
        s.effects.propagation.eye_pass = eye;
        return render(s, runs);
    };
    std::printf("Indirect light at light res %d, blend_axes off (the default: one direct and one indirect sweep; "
                "angle 30 deg, Phong 4, transport colour 0.6); errors on the indirect AOV against the row marked ref.\n\n",
                res);
    std::printf("| blur taps | chroma sub. | eye pass | light_grid (s) | propagation (s) | march (s) | total (s) | "
                "rel. RMSE | bias |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    auto row = [](int samples, bool chroma, bool eye, const Render& r, const std::string& err) {
        std::printf("| %d | %s | %s | %.3f | %.3f | %.3f | %.3f | %s |\n", samples, chroma ? "on" : "off",
                    eye ? "on" : "off", r.light_grid, r.propagation, r.march, r.total(), err.c_str());
    };
    const Render taps32 = indirectRender(32, false, false);
    row(32, false, false, taps32, "ref | ref");
    PlotSeries by_taps{d.name + ": indirect, taps vs 32 taps", color, {}};
    by_taps.dotted = true;
    Render full;   // 9 taps: the reference of the chroma and eye rows
    for (int samples : quick ? std::vector<int>{1, 9} : std::vector<int>{1, 5, 9, 17}) {
        Render r = indirectRender(samples, false, false);
        const Error e = aovError(r.image, taps32.image, &kernel::VxPixel::indirect);
        row(samples, false, false, r, errorCell(e) + (samples == 9 ? " (ref below)" : ""));
        by_taps.points.push_back({r.total(), e.rel_rmse, std::to_string(samples)});
        if (samples == 9) full = std::move(r);
    }
    const Render chroma = indirectRender(9, true, false);
    row(9, true, false, chroma, errorCell(aovError(chroma.image, full.image, &kernel::VxPixel::indirect)));
    const Render eye = indirectRender(9, false, true);
    row(9, false, true, eye, errorCell(aovError(eye.image, full.image, &kernel::VxPixel::indirect)));
    std::printf("\nIndirect share of the image: the indirect AOV's mean is %.0f%% of the direct AOV's (9 taps).\n\n",
                100.0 * meanAov(full.image, ref.image, &kernel::VxPixel::indirect) /
                    meanAov(full.image, ref.image, &kernel::VxPixel::direct));
    plot.push_back(by_taps);
}

}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);   // progress shows when redirected (a full run takes minutes)
    bench::Options options;
    if (!bench::parseOptions(argc, argv, "voxlux_bench_propagation", bench::sourceDir() + "/../shared/data", options)) return 2;
    const std::string& data = options.data;
    const std::string& svg = options.svg;
    const bool quick = options.quick, paper = options.paper, sweeps = options.sweeps;
    if (paper) paperComparison(quick);
    if (!sweeps) return 0;

    const std::vector<Dataset> sets = {
        {"smoke", data + "/arnold-usd/smoke.vdb", "density", false, 2.0f},
        {"fire", data + "/blender/fire/fluid_data_0040.vdb", "density", true, 4.0f},
        {"cloud", data + "/disney-wdas-cloud/wdas_cloud_sixteenth.vdb", "density", false, 0.1f}};
    const char* colors[] = {"#1f77b4", "#ff7f0e", "#d62728"};
    std::vector<PlotSeries> plot;
    std::vector<BlendPair> blends;
    for (size_t i = 0; i < sets.size(); ++i) {
        if (!std::filesystem::exists(sets[i].file)) {
            std::printf("%s: %s absent, skipped\n", sets[i].name.c_str(), sets[i].file.c_str());
            continue;
        }
        sweep(sets[i], quick, plot, colors[i], blends);
    }
    if (!blends.empty()) {
        std::printf("## blend_axes on against off (the default), direct light against the ray-marched reference\n\n");
        std::printf("| cache | light res | rel. RMSE, on | rel. RMSE, off | on / off - 1 | bias, on | bias, off | "
                    "propagation on (ms) | propagation off (ms) | on / off |\n|---|---|---|---|---|---|---|---|---|---|\n");
        for (const BlendPair& b : blends)
            std::printf("| %s | %s | %.4f | %.4f | %+.1f%% | %+.4f | %+.4f | %.1f | %.1f | %.1fx |\n", b.cache.c_str(),
                        b.res.c_str(), b.on.rel_rmse, b.off.rel_rmse, 100.0 * (b.on.rel_rmse / b.off.rel_rmse - 1.0),
                        b.on.bias, b.off.bias, 1e3 * b.prop_on, 1e3 * b.prop_off, b.prop_on / std::max(b.prop_off, 1e-6));
        std::printf("\n");
    }
    if (!svg.empty() && !plot.empty()) {
        writeLogLogSvg(svg, {{"Propagation: image error against time (CPU, 2 cores)",
                              "light grid + propagation + march (s)", "relative RMSE (direct / indirect AOV)", plot}});
        std::printf("wrote %s\n", svg.c_str());
    }
    return 0;
}
