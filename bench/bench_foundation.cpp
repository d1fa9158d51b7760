// Stage timings of the foundation pipeline on one cache (default: the shared Houdini smoke),
// for both backends: load, brick, classify, march without and with ray-marched shadows (and on the
// CPU with the tricubic filter, against the step, across empty space, and through several
// volumes), write.
// Prints figures; it asserts nothing. docs/performance.md quotes its output.
//
//   build/voxlux_bench [cache.vdb] [--res 512] [--backends cpu,gl] [--repeats 3]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "source_dir.h"
#include "volume/brick_atlas.h"
#include "scene/camera.h"
#include "io/exr_writer.h"
#include "kernel/kernel_inputs.h"
#include "backend/backend_choice.h"
#include "volume/page_table.h"
#include "render/renderer.h"
#include "volume/volume_stages.h"
#include "volume/vdb_loader.h"

namespace {

using namespace voxlux;

// Best wall time of `repeats` runs of `work`, in seconds.
double best(int repeats, const std::function<void()>& work) {
    double best = 1e30;
    for (int i = 0; i < repeats; ++i) {
        auto start = std::chrono::steady_clock::now();
        work();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
}

double totalSamples(const RenderImage& img) {
    double n = 0;
    for (const auto& p : img.pixels) n += p.samples;
    return n;
}

// The cache's density with a copy of it `offset` voxels away: two parts with empty space between.
LoadedVolume withCopyAt(const LoadedVolume& one, openvdb::Coord offset) {
    openvdb::FloatGrid::Ptr two = one.density->deepCopy();
    auto acc = two->getAccessor();
    for (auto it = one.density->cbeginValueOn(); it; ++it) {
        const openvdb::CoordBBox box = it.getBoundingBox();
        for (auto c = box.begin(); c; ++c) acc.setValue(*c + offset, *it);
    }
    LoadedVolume v = one;
    v.density = two;
    return v;
}

// The march's cost across empty space: the cache alone, then with a copy of it behind it along the
// camera's view, 2 and 9 of the cache's diagonals away (a gap of 1 and 8 diagonals), with only
// empty bricks between the parts. The camera stays the one-part framing, so rays cross the gap
// into the copy.
void emptySpaceRows(const LoadedVolume& volume, const Scene& scene, const Camera& camera, int repeats) {
    const glm::vec3 forward = glm::normalize(camera.look_at - camera.position);
    const glm::vec3 axis_forward = glm::vec3(glm::inverse(volume.index_to_world) * glm::vec4(forward, 0.0f));
    const openvdb::CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    const float diagonal = float(box.dim().asVec3d().length());
    auto cpu = makeCpuBackend();
    std::printf("  cpu march without shadows, the cache alone and with a copy of it behind it:\n");
    double alone = 0.0;
    for (float gap_diagonals : {0.0f, 1.0f, 8.0f}) {
        const glm::vec3 shift = glm::normalize(axis_forward) * diagonal * (1.0f + gap_diagonals);
        const LoadedVolume parts = gap_diagonals == 0.0f ? volume
                                                       : withCopyAt(volume, openvdb::Coord(int(std::lround(shift.x / 8)) * 8,
                                                                                            int(std::lround(shift.y / 8)) * 8,
                                                                                            int(std::lround(shift.z / 8)) * 8));
        const BrickAtlas atlas = buildBrickAtlas(parts);
        const PageTable pages = classifiedPageTable(atlas, scene);
        const glm::ivec3 span = pages.bricks_max - pages.bricks_min + 1;
        const double box_bricks = double(span.x) * span.y * span.z;
        KernelInputs inputs = makeKernelInputs(scene, atlas, pages, 0.0f, kXyzD65ToAcescg, {&camera, {}});
        RenderImage image;
        const double t = best(repeats, [&] { image = cpu->march(inputs); });
        if (gap_diagonals == 0.0f) alone = t;
        char label[64];
        std::snprintf(label, sizeof label, gap_diagonals == 0.0f ? "alone" : "copy %.0f diagonals behind", 1.0f + gap_diagonals);
        std::printf("    %-26s %9.4f s  %5.2fx alone  %6zu bricks  %9.0f empty bricks in their box  %7.1f M samples\n",
                    label, t, t / alone, pages.occupied, box_bricks - double(pages.occupied), totalSamples(image) / 1e6);
    }
}

// The march through several volumes (shaders/vx_volumes.h): the cache as one volume, then as 2 and
// 10 instances side by side (the default camera framing them all), the march's time and the atlas
// it reads. The instances take the several-volumes march, sample by sample; the one volume takes
// its own, in SIMD batches.
void severalVolumesRows(const std::string& cache, const Scene& base, int repeats) {
    std::printf("  cpu march without shadows through several volumes (instances of the cache in a row):\n");
    const LoadedVolume volume = loadVolume(cache, base.volume());
    const openvdb::CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    glm::vec3 lo, hi;
    voxelBoxWorldBounds(volume.index_to_world, box, lo, hi);
    for (int instances : {0, 2, 10}) {
        Scene scene = base;
        scene.render.backend = Backend::Cpu;
        scene.effects.shadows = ShadowMethod::None;
        for (int i = 0; i < instances; ++i) {
            VolumeTransform t;
            t.translate = glm::vec3(float(i) * 1.1f * (hi.x - lo.x), 0.0f, 0.0f);
            scene.volume().instances.push_back(t);
        }
        FrameResult result;
        double march = 1e30;
        for (int r = 0; r < repeats; ++r) {
            result = Renderer(scene).render(std::nullopt, false);
            for (const auto& [stage, seconds] : result.stage_seconds)
                if (stage == "march") march = std::min(march, seconds);
        }
        char label[64];
        std::snprintf(label, sizeof label, instances == 0 ? "one volume" : "%d instances", instances);
        std::printf("    %-26s %9.4f s  atlas %7.1f MB  %7.1f M samples\n", label, march, double(result.atlas_bytes) / 1e6,
                    totalSamples(result.image) / 1e6);
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::string cache = bench::sourceDir() + "/../shared/data/arnold-usd/smoke.vdb";
    int res = 512, repeats = 3;
    std::vector<std::string> backends{"cpu", "gl"};
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--res") && i + 1 < argc) res = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) repeats = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--backends") && i + 1 < argc) {
            backends.clear();
            std::string list = argv[++i];
            for (size_t at = 0; at <= list.size();) {
                size_t comma = list.find(',', at);
                backends.push_back(list.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
                at = comma == std::string::npos ? list.size() + 1 : comma + 1;
            }
        } else cache = argv[i];
    }
    if (!std::filesystem::exists(cache)) {
        std::fprintf(stderr, "voxlux_bench: %s not found (pass a .vdb)\n", cache.c_str());
        return 2;
    }

    Scene scene;
    scene.volume().path = cache;
    scene.render.width = scene.render.height = res;
    scene.render.step = 0.5f;
    scene.lights = {defaultKeyLight()};

    LoadedVolume volume;
    BrickAtlas atlas;
    PageTable pages;
    const double tLoad = best(repeats, [&] { volume = loadVolume(cache, scene.volume()); });
    const double tBrick = best(repeats, [&] { atlas = buildBrickAtlas(volume); });
    const double tClassify = best(repeats, [&] { pages = classifiedPageTable(atlas, scene); });
    const Camera camera = frameActiveVoxels(volume, scene);

    std::printf("voxlux_bench: %s, %dx%d, step %.2f voxel, 1 directional light\n", cache.c_str(), res, res,
                scene.render.step);
    std::printf("  active voxels %llu, bricks %zu, atlas %.1f MB, %u threads\n",
                static_cast<unsigned long long>(atlas.active_voxels), pages.occupied, atlas.bytes() / 1e6,
                std::thread::hardware_concurrency());
    std::printf("  %-34s %9.4f s\n", "load", tLoad);
    std::printf("  %-34s %9.4f s\n", "brick", tBrick);
    std::printf("  %-34s %9.4f s\n", "classify", tClassify);

    RenderImage image;
    std::map<ShadowMethod, double> cpu_trilinear;  // the cpu rows' times, for the tricubic ratios
    for (const auto& name : backends) {
        std::unique_ptr<KernelBackend> backend;
        try {
            backend = makeBackend(name == "gl" ? Backend::Gl : Backend::Cpu);
        } catch (const std::exception& e) {
            std::printf("  %s backend unavailable: %s\n", name.c_str(), e.what());
            continue;
        }
        for (ShadowMethod shadows : {ShadowMethod::None, ShadowMethod::Raymarch}) {
            scene.effects.shadows = shadows;
            KernelInputs inputs = makeKernelInputs(scene, atlas, pages, 0.0f, kXyzD65ToAcescg, {&camera, {}});
            backend->march(inputs);  // warm-up: GL compiles its program and uploads here
            const int runs = shadows == ShadowMethod::None ? repeats : 1;
            const double t = best(runs, [&] { image = backend->march(inputs); });
            const double samples = totalSamples(image);
            if (name == "cpu") cpu_trilinear[shadows] = t;
            std::string label = "march " + backend->name() + (shadows == ShadowMethod::None ? ", no shadows" : ", shadows");
            std::printf("  %-34s %9.4f s  %7.1f M camera samples", label.c_str(), t, samples / 1e6);
            if (shadows == ShadowMethod::None) std::printf("  %7.1f M samples/s", samples / t / 1e6);
            std::printf("\n");
        }
    }

    // The tricubic filter's cost on the CPU (the GL rows would take minutes on llvmpipe), against
    // the cpu rows above.
    for (const auto& [shadows, trilinear] : cpu_trilinear) {
        Scene cubic = scene;
        cubic.effects.shadows = shadows;
        cubic.render.filter = Filter::Tricubic;
        const PageTable cubic_pages = classifiedPageTable(atlas, cubic);
        KernelInputs inputs = makeKernelInputs(cubic, atlas, cubic_pages, 0.0f, kXyzD65ToAcescg, {&camera, {}});
        auto cpu = makeCpuBackend();
        const double tricubic = best(shadows == ShadowMethod::None ? repeats : 1, [&] { image = cpu->march(inputs); });
        const std::string label = std::string("march cpu, tricubic, ") + (shadows == ShadowMethod::None ? "no shadows" : "shadows");
        std::printf("  %-34s %9.4f s  %5.2fx the cpu row above\n", label.c_str(), tricubic, tricubic / trilinear);
    }

    // Where the CPU march's time goes: a huge step leaves only ray setup and brick traversal; the
    // slope between small steps is the marginal cost of a sample.
    std::printf("  cpu march without shadows against step (fixed cost vs per-sample cost):\n");
    for (float step : {32.0f, 4.0f, 1.0f, 0.5f, 0.25f, 0.125f}) {
        scene.effects.shadows = ShadowMethod::None;
        scene.render.step = step;
        KernelInputs inputs = makeKernelInputs(scene, atlas, pages, 0.0f, kXyzD65ToAcescg, {&camera, {}});
        auto cpu = makeCpuBackend();
        const double t = best(repeats, [&] { image = cpu->march(inputs); });
        const double samples = totalSamples(image);
        std::printf("    step %6.3f voxel  %9.4f s  %7.1f M samples  %7.1f M samples/s\n", step, t, samples / 1e6,
                    samples / t / 1e6);
    }

    scene.render.step = 0.5f;
    emptySpaceRows(volume, scene, camera, repeats);
    severalVolumesRows(cache, scene, repeats);

    const std::string out = (std::filesystem::temp_directory_path() / "voxlux_bench.exr").string();
    OutputSpec spec;
    const double tWrite = best(repeats, [&] { writeExr(out, image, spec, ExrMetadata{}); });
    std::filesystem::remove(out);
    std::printf("  %-34s %9.4f s\n", "write (half, zip)", tWrite);
    return 0;
}
