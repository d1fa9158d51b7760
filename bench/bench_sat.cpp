// What the Extinction-SAT lighting costs and how accurate it is (docs/accuracy-sat.md).
//
// 1. The paper's GTX 285 figures (Schlegel 2011, Sec. 4) against the CPU backend on a full 256^3
//    light grid, and the SAT build against a STREAM-style copy measured here.
// 2. On real caches, sweeps of each quality knob (light resolution, AO shells, cone cuboids):
//    the time of every pass and the final image's error against a reference render.
// Prints figures and writes an error-against-time plot; it asserts nothing.
//
//   build/voxlux_bench_sat [--data DIR] [--svg docs/accuracy-sat.svg] [--quick] [--paper-only | --sweeps-only]

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "source_dir.h"
#include "bench_timing.h"
#include "scene/camera.h"
#include "lighting/extinction_sat/cpu_light_pass.h"
#include "kernel/kernel_backend.h"
#include "render/renderer.h"
#include "lighting/extinction_sat/summed_volume.h"
#include "tools/svg_plot.h"

namespace {

using namespace voxlux;

using bench::best;
using bench::copyBandwidth;
using bench::seconds;

// A full light grid of n^3 cells of smooth noise, every cell needed (the paper computes all).
LightGrid syntheticGrid(int n, int planes) {
    LightGrid g;
    g.dims = glm::ivec3(n);
    g.planes = planes;
    g.values.resize(g.cells() * planes);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (auto& v : g.values) v = u(rng) * u(rng) * 4.0f;
    g.needed.assign(g.cells(), 1);
    return g;
}

LightPass passOver(const LightGrid& g, const SummedVolume& sat, const std::vector<kernel::VxLight>& lights) {
    LightPass p;
    p.lights = &lights;
    p.sat = &sat;
    p.sat_generation = 1;
    p.needed = &g.needed;
    p.params.dims = g.dims;
    p.params.planes = sat.planes;
    p.params.quantum = sat.quantum;
    p.params.light_to_world = glm::mat4(1.0f);
    p.params.world_to_light = glm::mat4(1.0f);
    p.params.cache_floats = 1;
    return p;
}

void paperComparison(int repeats) {
    const int n = 256;
    std::printf("## Against Schlegel et al. 2011 (GTX 285), full %d^3 light grid, CPU backend, %u threads\n\n", n,
                std::thread::hardware_concurrency());
    const double copy = copyBandwidth();
    std::printf("STREAM-style copy bandwidth (same binary): %.1f GB/s\n\n", copy / 1e9);
    std::printf("| pass | paper (s) | voxlux (s) | paper / voxlux |\n|---|---|---|---|\n");
    auto row = [](const char* pass, double paper, double ours) {
        std::printf("| %s | %s | %.3f | %s |\n", pass, paper > 0 ? std::to_string(paper).substr(0, 5).c_str() : "-", ours,
                    paper > 0 ? (std::to_string(paper / ours).substr(0, 4) + "x").c_str() : "-");
    };

    // The roofline of a streaming pass: `bytes` moved in `t` seconds against the copy bandwidth.
    auto roofline = [&](const char* what, double bytes, double t) {
        std::printf("|  (%s %.0f MB: %.1f GB/s, %.0f%% of copy bandwidth) | | | |\n", what, bytes / 1e6, bytes / t / 1e9,
                    100.0 * bytes / t / copy);
    };
    SummedVolume sat;
    for (int planes : {1, 4}) {
        const LightGrid g = syntheticGrid(n, planes);
        sat = SummedVolume{};
        const double first = seconds([&] { buildSummedVolume(g, sat); });
        const double t = best(repeats, [&] { buildSummedVolume(g, sat); });  // storage reused, as across frames
        std::printf("|  (first build, allocating: %.3f s) | | | |\n", first);
        row(planes == 1 ? "SAT build, extinction" : "SAT build, extinction + RGB bleeding", planes == 4 ? 0.311 : 0.0, t);
        // At least 4 bytes in and 12 out per cell and plane: the floor any SAT build must move.
        roofline("moves >=", double(g.cells()) * planes * (4.0 + 12.0), t);
    }
    // A light pass reads the 12-byte table and writes a 4-byte channel. It moves at least the
    // table once and the channel; a pass that streams the table once per cuboid (each cuboid's
    // corner lines read once from memory) moves 12 B per cell and cuboid.
    const auto lightPassRooflines = [&](int cuboids, double t) {
        const double cells = double(n) * n * n;
        roofline("moves >=", cells * (12.0 + 4.0), t);
        roofline("if each cuboid streams the table,", cells * (12.0 * cuboids + 4.0), t);
    };
    const LightGrid g = syntheticGrid(n, 1);
    buildSummedVolume(g, sat);
    LightCache cache;
    cache.channels = 1;
    cache.values.assign(g.cells(), 0.0f);
    std::vector<kernel::VxLight> lights(2);
    lights[0].type = VX_LIGHT_DIRECTIONAL;
    lights[0].direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.2f));
    lights[1].type = VX_LIGHT_POINT;
    lights[1].position = glm::vec3(100.0f, 200.0f, 140.0f);
    const std::map<int, double> paper_ao = {{3, 0.0307}, {7, 0.0791}, {11, 0.1382}};
    for (int shells : {3, 7, 11}) {
        LightPass p = passOver(g, sat, lights);
        p.params.light = -1;
        p.params.shells = shells;
        p.params.shell_radius = 8.0f;
        p.params.cell_world = 1.0f;
        const double t = best(repeats, [&] { fillLightChannelCpu(p, cache); });
        row(("AO, " + std::to_string(shells) + " shells").c_str(), paper_ao.at(shells), t);
        lightPassRooflines(shells, t);
    }
    const std::map<int, double> paper_cone = {{20, 0.1821}, {50, 0.2671}};
    for (int light : {0, 1})
        for (int samples : {20, 50}) {
            LightPass p = passOver(g, sat, lights);
            p.params.light = light;
            p.params.cone_tan = std::tan(glm::radians(2.0f));
            p.params.cone_cuboids = samples;
            p.params.cone_growth = 0.1f;
            p.params.cone_growth_total = std::pow(1.1f, float(samples));
            const double t = best(light == 0 ? repeats : 1, [&] { fillLightChannelCpu(p, cache); });
            const std::string label = std::string(light == 0 ? "cone shadows, directional, " : "cone shadows, point, ") +
                                      std::to_string(samples) + " cuboids";
            row(label.c_str(), light == 0 ? paper_cone.at(samples) : 0.0, t);
            lightPassRooflines(samples, t);
        }
    std::printf("\n");
}

// Stage seconds: the scenes below have either cone shadows or ambient occlusion, so the
// light_cache stage times one of them.
struct Render {
    double sat = 0, light_grid = 0, light_cache = 0, march = 0;
    RenderImage image;
    double light() const { return light_grid + sat + light_cache; }
};

// `scene`, best of two renders on fresh renderers.
Render render(const Scene& scene) {
    bench::TimedRender t = bench::renderFresh(scene, 2);
    return {t("sat"), t("light_grid"), t("light_cache"), t("march"), std::move(t.image)};
}

struct Error {
    double rmse = 0, max_abs = 0;
};

// On scene-linear RGB.
Error imageError(const RenderImage& a, const RenderImage& ref) {
    Error e;
    double sum = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.pixels[i].rgba[c]) - ref.pixels[i].rgba[c];
            sum += d * d;
            e.max_abs = std::max(e.max_abs, std::abs(d));
        }
    e.rmse = std::sqrt(sum / (3.0 * a.pixels.size()));
    return e;
}

struct Dataset {
    std::string name, file;
    glm::ivec2 res;
    float density_scale;
};

Light keyLight() {
    Light l;
    l.direction = glm::normalize(glm::vec3(-0.6f, -0.7f, -0.3f));
    l.intensity = 6.0f;
    return l;
}

void sweep(const Dataset& d, bool quick, std::vector<PlotSeries>& plot, const char* color_shadow,
           const char* color_ao) {
    Scene base;
    base.volume().path = d.file;
    base.render.width = d.res.x;
    base.render.height = d.res.y;
    base.render.backend = Backend::Cpu;
    base.volume().material.density_scale = d.density_scale;

    // Shadows: one directional key light; the reference marches a shadow ray per sample at half
    // a voxel (render.shadow_step 0.5).
    Scene shadowed = base;
    shadowed.lights = {keyLight()};
    shadowed.render.shadow_step = 0.5f;
    const Render ref = render(shadowed);
    std::printf("## %s (%s), %dx%d\n\n", d.name.c_str(), d.file.c_str(), d.res.x, d.res.y);
    std::printf("Reference: ray-marched shadows (shadow step 0.5 voxel), march %.3f s.\n\n", ref.march);
    std::printf("| light res | cone cuboids | light grid (s) | SAT (s) | shadows (s) | march (s) | RMSE | max abs |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    PlotSeries by_res{d.name + ": light res 64..256, 20 cuboids", color_shadow, {}};
    PlotSeries by_cuboids{d.name + ": 12, 20, 50 cuboids, res 256", color_shadow, {}};
    by_cuboids.dashed = true;
    auto shadowPoint = [&](int res, int samples, PlotSeries& series, const std::string& label) {
        Scene s = shadowed;
        s.effects.shadows = ShadowMethod::SatCone;
        s.effects.light_resolution = res;
        s.effects.cone = {1.0f, samples, 0.1f};
        const Render r = render(s);
        const Error e = imageError(r.image, ref.image);
        std::printf("| %d | %d | %.3f | %.3f | %.3f | %.3f | %.4g | %.4g |\n", res, samples, r.light_grid, r.sat,
                    r.light_cache, r.march, e.rmse, e.max_abs);
        series.points.push_back({r.light() + r.march, e.rmse, label});
    };
    for (int res : {64, 128, 192, 256}) shadowPoint(res, 20, by_res, std::to_string(res));
    for (int samples : {12, 50}) shadowPoint(128, samples, by_res, "");  // table only
    by_res.points.resize(4);
    for (int samples : quick ? std::vector<int>{} : std::vector<int>{12, 20, 50})
        shadowPoint(256, samples, by_cuboids, std::to_string(samples));
    std::printf("\n");

    // Ambient occlusion: an ambient light only. AO has no ray-marched counterpart, so the reference
    // is the same model with a shell at every ring of cells out to the radius (64 shells).
    Scene ambient = base;
    Light sky;
    sky.type = LightType::Ambient;
    sky.intensity = 1.0f;
    ambient.lights = {sky};
    // A neighbourhood of 1/8 of the volume's longest side (16 cells at light res 128).
    const LoadedVolume volume = loadVolume(d.file, base.volume());
    const openvdb::CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    glm::vec3 lo, hi;
    worldBounds(volume.index_to_world, glm::vec3(box.min().x(), box.min().y(), box.min().z()),
                glm::vec3(box.max().x(), box.max().y(), box.max().z()), lo, hi);
    const float radius = 0.125f * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    ambient.effects.ambient_occlusion = AmbientOcclusion{64, radius};
    ambient.effects.light_resolution = 128;
    const Render ao_ref = render(ambient);
    std::printf("AO reference: radius %.3g (1/8 of the longest side), 64 shells (one per ring of cells) at light res "
                "128, AO pass %.3f s.\n\n",
                radius, ao_ref.light_cache);
    std::printf("| light res | shells | light grid (s) | SAT (s) | AO (s) | march (s) | RMSE | max abs |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    PlotSeries ao_series{d.name + ": AO 3, 7, 11 shells (vs 64)", color_ao, {}};
    for (int shells : {3, 7, 11}) {
        Scene s = ambient;
        s.effects.ambient_occlusion->shells = shells;
        const Render r = render(s);
        const Error e = imageError(r.image, ao_ref.image);
        std::printf("| 128 | %d | %.3f | %.3f | %.3f | %.3f | %.4g | %.4g |\n", shells, r.light_grid, r.sat,
                    r.light_cache, r.march, e.rmse, e.max_abs);
        ao_series.points.push_back({r.light() + r.march, e.rmse, std::to_string(shells)});
        ao_series.dotted = true;
    }
    std::printf("\n");
    plot.push_back(by_res);
    if (!by_cuboids.points.empty()) plot.push_back(by_cuboids);
    plot.push_back(ao_series);
}

}  // namespace

int main(int argc, char** argv) {
    bench::Options options;
    if (!bench::parseOptions(argc, argv, "voxlux_bench_sat", bench::sourceDir() + "/../shared/data", options)) return 2;
    const std::string& data = options.data;
    const std::string& svg = options.svg;
    const bool quick = options.quick, paper = options.paper, sweeps = options.sweeps;
    if (paper) paperComparison(quick ? 1 : 3);
    if (!sweeps) return 0;

    const std::vector<Dataset> sets = {{"smoke", data + "/arnold-usd/smoke.vdb", {240, 400}, 2.0f},
                                       {"cloud", data + "/disney-wdas-cloud/wdas_cloud_sixteenth.vdb", {400, 300}, 0.1f}};
    std::vector<PlotSeries> plot;
    const char* colors[][2] = {{"#1f77b4", "#9ecae1"}, {"#d62728", "#fc9272"}};
    for (size_t i = 0; i < sets.size(); ++i) {
        if (!std::filesystem::exists(sets[i].file)) {
            std::printf("%s: %s absent, skipped\n", sets[i].name.c_str(), sets[i].file.c_str());
            continue;
        }
        sweep(sets[i], quick, plot, colors[i][0], colors[i][1]);
    }
    if (!svg.empty() && !plot.empty()) {
        writeLogLogSvg(svg, {{"Extinction-SAT lighting: image error against time (CPU, 2 cores)",
                              "light passes + march (s)", "RMSE of scene-linear RGB", plot}});
        std::printf("wrote %s\n", svg.c_str());
    }
    return 0;
}
