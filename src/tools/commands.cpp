#include "tools/commands.h"

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "scene/camera.h"
#include "core/error.h"
#include "io/exr_writer.h"
#include "core/frame_pattern.h"
#include "volume/make_cloud.h"
#include "render/light_edits.h"
#include "render/renderer.h"
#include "scene/scene_json.h"
#include "volume/vdb_loader.h"

namespace voxlux {
namespace {

bool isSceneFile(const std::string& path) {
    auto ext = std::filesystem::path(path).extension().string();
    return ext == ".json";
}

// The quick form: a .vdb with default light and framing (a camera is filled in by `scene`).
Scene quickScene(const std::string& vdb) {
    Scene s;
    s.volume.path = vdb;
    s.lights.push_back(defaultKeyLight());
    return s;
}

// The frames a render covers, taken one at a time: a range is never expanded up front, so
// `--frames 1-2000000000` costs nothing before its first frame.
struct FrameSpan {
    std::optional<int> first;   // none: one file without a frame pattern
    int last = 0;

    int64_t count() const { return first ? int64_t(last) - *first + 1 : 1; }
    std::optional<int> at(int64_t k) const { return first ? std::optional<int>(int(*first + k)) : std::nullopt; }
};

FrameSpan framesOf(const Scene& s) {
    if (!hasFramePattern(s.volume.path)) return {};
    if (!s.volume.frames)
        throw InputError(s.volume.path + ": path has a #### frame pattern; set volume.frames or pass --frames");
    if (!hasFramePattern(s.output.path) && (*s.volume.frames)[0] != (*s.volume.frames)[1])
        throw InputError(s.output.path + ": several frames need a #### pattern in the output path");
    if (!s.output.preview.empty() && !hasFramePattern(s.output.preview) && (*s.volume.frames)[0] != (*s.volume.frames)[1])
        throw InputError(s.output.preview + ": several frames need a #### pattern in the preview path");
    return {(*s.volume.frames)[0], (*s.volume.frames)[1]};
}

size_t peakRssBytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return size_t(u.ru_maxrss) * 1024;
}

std::string secondsText(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f s", s);
    return buf;
}

const char* modeName(LightUpdate::Mode m) {
    return m == LightUpdate::Mode::Kept ? "kept" : m == LightUpdate::Mode::Selective ? "selective" : "entire";
}

nlohmann::json describeUpdate(const LightRigUpdate& u, const std::string& what) {
    nlohmann::json j = {{"edit", what}, {"seconds", u.seconds}};
    for (const auto& [stage, seconds] : u.stage_seconds) j["stages"][stage] = seconds;
    if (const auto& l = u.lighting) {
        j["mode"] = modeName(l->mode);
        j["reason"] = l->reason;
        j["lights"] = l->lights;
        j["lights_out"] = l->lights_out;
        j["lights_in"] = l->lights_in;
        j["sweeps"] = l->sweeps;
        j["passes"] = l->passes;
        j["slices"] = l->slices;
    }
    return j;
}

// `render --light-edit`: the scene's first update, then each edit applied through a LightRig and
// timed on its own, then the final frame marched and written.
int runLightEdits(const Scene& scene, const std::string& edits_file, std::optional<int> frame,
                  const std::optional<std::string>& stats_file) {
    const std::vector<LightEdit> edits = loadLightEdits(edits_file);
    if (stats_file) checkWritable(*stats_file);
    Renderer renderer(scene);
    LightRig rig(renderer, scene);
    {   // every edit is checked before anything renders
        LightRig dry = rig;
        for (const auto& e : edits) applyLightEdit(dry, e);
    }
    nlohmann::json log = nlohmann::json::array();
    auto report = [&](const std::string& what, const LightRigUpdate& u) {
        char line[160];
        std::snprintf(line, sizeof line, "%-28s %8.4f s", what.c_str(), u.seconds);
        std::cout << line;
        if (const auto& l = u.lighting) {
            std::snprintf(line, sizeof line, "  %-9s -%d +%d of %2d lights %3d sweeps %2d passes %6lld slices", modeName(l->mode),
                          l->lights_out, l->lights_in, l->lights, l->sweeps, l->passes, l->slices);
            std::cout << line << (l->reason.empty() ? "" : "  (" + l->reason + ")");
        }
        std::cout << "\n";
        log.push_back(describeUpdate(u, what));
    };
    report("initial", rig.apply(frame));
    for (size_t k = 0; k < edits.size(); ++k) {
        const std::string what = std::to_string(k + 1) + ": " + applyLightEdit(rig, edits[k]);
        report(what, rig.apply(frame));
    }
    FrameResult r = renderer.renderToFile(frame, false);
    for (const auto& w : r.warnings) std::cerr << "voxlux: warning: " << w << "\n";
    std::cout << "wrote " << r.path << " (" << renderer.backendName() << ", " << edits.size() << " light edits)\n";
    if (stats_file)
        writeFileAtomically(*stats_file, jsonText(nlohmann::json({{"backend", renderer.backendName()}, {"light_edits", log},
                                                                  {"peak_rss_bytes", peakRssBytes()}}),
                                                  2) + "\n");
    return 0;
}

}  // namespace

int runRender(const RenderCommand& cmd) {
    Scene scene = isSceneFile(cmd.input) ? loadSceneFile(cmd.input) : quickScene(cmd.input);
    scene = applyOverrides(scene, cmd.overrides);
    if (cmd.explain) {
        std::cout << Renderer(scene).graph().explain(scene);
        return 0;
    }
    const FrameSpan frames = framesOf(scene);
    const bool sequence = frames.first.has_value();
    if (cmd.light_edits) return runLightEdits(scene, *cmd.light_edits, frames.first, cmd.stats);

    if (cmd.stats) checkWritable(*cmd.stats);  // before any frame: every output or none
    Renderer renderer(scene);
    nlohmann::json stats = {{"backend", renderer.backendName()}, {"frames", nlohmann::json::array()}};
    size_t emptyFrames = 0;
    for (int64_t k = 0; k < frames.count(); ++k) {
        const std::optional<int> frame = frames.at(k);
        FrameResult r = renderer.renderToFile(frame, sequence);
        for (const auto& w : r.warnings) std::cerr << "voxlux: warning: " << w << "\n";
        emptyFrames += r.empty;
        std::cout << "wrote " << r.path << (r.preview_path.empty() ? "" : " and " + r.preview_path) << " ("
                  << renderer.backendName() << ", " << r.bricks << " bricks)";
        nlohmann::json stages;
        double total = 0;
        for (const auto& [stage, seconds] : r.stage_seconds) {
            std::cout << "  " << stage << " " << secondsText(seconds);
            stages[stage] = seconds;
            total += seconds;
        }
        std::cout << "\n";
        nlohmann::json fj = {{"stages", stages}, {"total_seconds", total}, {"bricks", r.bricks},
                             {"atlas_bytes", r.atlas_bytes}, {"empty", r.empty}};
        if (frame) fj["frame"] = *frame;
        stats["frames"].push_back(fj);
    }
    if (emptyFrames) std::cerr << "voxlux: warning: " << emptyFrames << " empty frame(s) rendered transparent\n";
    stats["peak_rss_bytes"] = peakRssBytes();
    if (cmd.stats) writeFileAtomically(*cmd.stats, jsonText(stats, 2) + "\n");
    return 0;
}

int runStudyCommand(const StudyCommand& cmd) {
    Scene scene = isSceneFile(cmd.input) ? loadSceneFile(cmd.input) : quickScene(cmd.input);
    scene = applyOverrides(scene, cmd.overrides);
    runStudy(scene, cmd.options, std::cout, std::cerr, isatty(STDERR_FILENO));
    return 0;
}

int runScene(const std::string& vdb, const SceneOverrides& overrides) {
    Scene scene = applyOverrides(quickScene(vdb), overrides);
    scene.camera = frameVolumeCamera(vdb, scene);
    std::cout << jsonText(sceneToJson(scene), 2) << "\n";
    return 0;
}

int runInfo(const std::string& vdb, bool json) {
    auto grids = summarizeFile(vdb);
    if (json) {
        nlohmann::json out = {{"file", vdb}, {"grids", nlohmann::json::array()}};
        for (const auto& g : grids) {
            nlohmann::json gj = {{"name", g.name}, {"type", g.value_type}, {"class", g.grid_class},
                                 {"active_voxels", g.active_voxels}, {"active_tiles", g.active_tiles},
                                 {"voxel_size", {g.voxel_size.x(), g.voxel_size.y(), g.voxel_size.z()}},
                                 {"bricks", g.bricks}};
            if (g.active_voxels > 0) {
                gj["bbox_min"] = {g.bbox.min().x(), g.bbox.min().y(), g.bbox.min().z()};
                gj["bbox_max"] = {g.bbox.max().x(), g.bbox.max().y(), g.bbox.max().z()};
            }
            out["grids"].push_back(gj);
        }
        std::cout << jsonText(out, 2) << "\n";
        return 0;
    }
    std::cout << vdb << ": " << grids.size() << (grids.size() == 1 ? " grid\n" : " grids\n");
    for (const auto& g : grids) {
        std::cout << "  " << g.name << "  " << g.value_type << "  " << g.grid_class << "\n"
                  << "    active voxels " << g.active_voxels << " (" << g.active_tiles << " active tiles)\n";
        if (g.active_voxels == 0) {
            std::cout << "    empty\n";
            continue;
        }
        const auto& b = g.bbox;
        std::cout << "    bbox (index) [" << b.min().x() << ", " << b.min().y() << ", " << b.min().z() << "] -> ["
                  << b.max().x() << ", " << b.max().y() << ", " << b.max().z() << "]  (" << b.dim().x() << " x "
                  << b.dim().y() << " x " << b.dim().z() << ")\n"
                  << "    voxel size " << g.voxel_size.x() << " " << g.voxel_size.y() << " " << g.voxel_size.z() << "\n"
                  << "    bricks (8^3) " << g.bricks << "\n";
    }
    return 0;
}

int runMakeCloud(const std::string& output, int resolution, unsigned seed) {
    initOpenVdb();
    CloudParams p;
    p.resolution = resolution;
    p.seed = seed;
    auto grid = makeCloud(p);
    grid->setSaveFloatAsHalf(true);
    writeAtomically(output, [&](const std::string& tmp) { openvdb::io::File(tmp).write({grid}); });
    std::cout << "wrote " << output << " (" << grid->activeVoxelCount() << " active voxels)\n";
    return 0;
}

}  // namespace voxlux
