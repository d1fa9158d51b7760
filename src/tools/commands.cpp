#include "tools/commands.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "scene/camera.h"
#include "core/error.h"
#include "io/exr_writer.h"
#include "core/frame_pattern.h"
#include "core/peak_memory.h"
#include "core/progress.h"
#include "tools/sequence_render.h"
#include "volume/make_cloud.h"
#include "grade/color_pipeline.h"
#include "optics/emission.h"
#include "optics/sky_model.h"
#include "scan/scan_import.h"
#include "render/light_edits.h"
#include "render/renderer.h"
#include "render/write_stage.h"
#include "scene/scene_json.h"
#include "volume/vdb_file.h"
#include "volume/vdb_loader.h"
#include "render/framing.h"
#include "tools/quick_form.h"
#if VOXLUX_HAS_VIEWER
#include "viewer/viewer_app.h"
#endif

namespace voxlux {
namespace {

bool isSceneFile(const std::string& path) {
    auto ext = std::filesystem::path(path).extension().string();
    return ext == ".json";
}

std::string secondsText(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f s", s);
    return buf;
}

std::string bytesText(size_t bytes) {
    char buf[32];
    if (bytes < 1024 * 1024) std::snprintf(buf, sizeof buf, "%.1f KiB", double(bytes) / 1024.0);
    else std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
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

// The scene a command renders: the scene file, or the quick form's, with the flags applied. What
// a sequence takes from its data is read from the whole sequence on disk, never from the frames
// asked for, so that any two sub-ranges of a shot cut together: a sequence without a camera gets
// one for all its frames on disk (or --frame-on's frame alone), and the quick form reads its
// choices from the fullest frame on disk (or --frame-on's); `notes` says what it chose.
Scene sceneFor(const std::string& input, const SceneOverrides& overrides, std::vector<std::string>& notes) {
    const bool quick = !isSceneFile(input);
    Scene scene = applyOverrides(quick ? quickScene(input) : loadSceneFile(input), overrides);
    std::optional<int> reference = overrides.frame_on;
    if (sequenceFrames(scene) && !reference && (quick || !scene.camera)) {
        const SequenceFraming framing = frameSequence(scene);
        reference = framing.fullest_frame;
        if (!scene.camera) {
            scene.camera = framing.camera;
            notes.push_back("camera framed on the frames on disk, " + framing.frames.text() + ", together (--frame-on N for one frame)");
        }
        if (framing.unreadable.count())
            notes.push_back("frames " + framing.unreadable.text() + " on disk cannot be read and are left out of what the data decides (" +
                            framing.unreadable_reason + ")");
    }
    if (sequenceFrames(scene) && !scene.camera)   // --frame-on
        scene.camera = frameVolumeCamera(expandFramePattern(scene.volume().path, *reference), scene);
    if (quick) scene = completeQuickScene(scene, overrides, reference, notes);
    return scene;
}

// Notes go to standard error (standard output holds results: a scene, a graph, the frames
// written), once the command has succeeded: a failing command prints its one error line only.
void printNotes(const std::vector<std::string>& notes) {
    for (const auto& n : notes) std::cerr << "voxlux: " << n << "\n";
}

// What `--explain` can check without rendering: the output path, the frame pattern, and that each
// file the first and last frames read exists and has the grids the scene names.
// Frames of the range not on disk do not stop a render (they fail, the others render): they are
// a note, as the render's own line.
std::vector<std::string> missingInputs(const Scene& scene, const SequenceOptions& sequence, std::vector<std::string>& notes) {
    std::vector<std::string> problems;
    std::vector<std::string> files{scene.volume().path}, outputs;
    try {
        if (const auto frames = sequenceFrames(scene)) {
            const FrameSet disk = framesOnDisk(scene.volume().path, *frames), present = frames->among(disk), missing = frames->notAmong(disk);
            if (present.count() == 0) {
                problems.push_back(scene.volume().path + ": no file of frames " + frames->text() + " exists" +
                                   (disk.count() ? " (on disk: frames " + disk.text() + ")" : ""));
                return problems;
            }
            if (missing.count()) notes.push_back("frames " + missing.text() + " of " + frames->text() + " are not on disk: they will fail, the others render");
            files = {expandFramePattern(scene.volume().path, present.first()), expandFramePattern(scene.volume().path, present.last())};
            outputs = frameOutputPaths(scene, present.first());
        } else {
            outputs = frameOutputPaths(scene, std::nullopt);
        }
    } catch (const InputError& e) {
        problems.push_back(e.what());
        return problems;
    } catch (const std::invalid_argument& e) {   // a frame pattern in a folder's name over too many frames
        problems.push_back(scene.volume().path + ": " + e.what());
        return problems;
    }
    if (const auto problem = outputPathProblem(scene)) {
        problems.push_back(*problem);
        outputs.clear();   // no path to check
    }
    if (sequence.stats) outputs.push_back(*sequence.stats);
    if (sequence.log_json) outputs.push_back(*sequence.log_json);
    for (const std::string& path : outputs)
        if (const auto problem = outputProblem(path)) problems.push_back(*problem);
    std::vector<std::string> grids{scene.volume().density.name};   // the first is the density, whose flag is --grid
    if (scene.volume().color) grids.push_back(scene.volume().color->name);
    for (const auto& e : scene.volume().emission) grids.push_back(e.grid.name);
    for (size_t k = 0; k < files.size() && (k == 0 || files[k] != files[0]); ++k) {
        try {
            if (!std::filesystem::exists(files[k])) throw InputError(files[k] + ": no such file");
            const VdbFile file(files[k]);
            for (size_t g = 0; g < grids.size(); ++g) {
                const bool found = std::any_of(file.grids().begin(), file.grids().end(),
                                               [&](const VdbFile::Grid& in) { return in.name == grids[g]; });
                if (!found) problems.push_back(file.noGridNamed(grids[g], g == 0 ? "--grid" : ""));
            }
        } catch (const InputError& e) {
            problems.push_back(e.what());
        }
    }
    return problems;
}

int explainRender(const RenderCommand& cmd) {
    Scene scene;
    std::vector<std::string> problems, notes;
    try {
        scene = sceneFor(cmd.input, cmd.overrides, notes);
    } catch (const InputError& e) {
        // The quick form reads its cache to choose its defaults: explain without them.
        if (isSceneFile(cmd.input)) throw;
        problems.push_back(e.what());
        scene = applyOverrides(quickScene(cmd.input), cmd.overrides);
    }
    for (const auto& p : missingInputs(scene, cmd.sequence, notes))
        if (std::find(problems.begin(), problems.end(), p) == problems.end()) problems.push_back(p);
    const Renderer renderer(scene);
    std::cout << renderer.graph().explain(renderer.scene());
    if (problems.empty()) {
        printNotes(notes);
        return 0;
    }
    std::cout << "\ncannot render:\n";
    for (const auto& p : problems) std::cout << "  " << p << "\n";
    std::cerr << "voxlux: error: " << problems.front()
              << (problems.size() > 1 ? " (and " + std::to_string(problems.size() - 1) + " more, listed above)" : "") << "\n";
    return kInputError;
}

}  // namespace

int runRender(const RenderCommand& cmd) {
    if (cmd.explain) return explainRender(cmd);
    std::vector<std::string> notes;
    const Scene scene = sceneFor(cmd.input, cmd.overrides, notes);
    if (cmd.light_edits) {
        if (cmd.sequence.resume || cmd.sequence.fail_fast || cmd.sequence.log_json)
            throw InputError("--light-edit: renders one frame; --resume, --fail-fast and --log-json are for sequences");
        const auto frames = sequenceFrames(scene);
        return runLightEdits(scene, *cmd.light_edits, frames ? std::optional<int>(frames->first()) : std::nullopt, cmd.sequence.stats);
    }
    const int status = renderSequence(scene, cmd.sequence, std::cout, std::cerr);
    printNotes(notes);
    return status;
}

int runFarmSubmit(const FarmSubmitCommand& cmd) {
    std::vector<std::string> notes;
    const Scene scene = sceneFor(cmd.input, cmd.overrides, notes);
    const int status = farmSubmit(scene, cmd.input, cmd.options, std::cout);
    printNotes(notes);
    return status;
}

int runStudyCommand(const StudyCommand& cmd) {
    std::vector<std::string> notes;
    const Scene scene = sceneFor(cmd.input, cmd.overrides, notes);
    runStudy(scene, cmd.options, std::cout);
    printNotes(notes);
    return 0;
}

int runCalibrateCommand(const CalibrateCommand& cmd) {
    std::vector<std::string> notes;
    Scene scene = sceneFor(cmd.input, cmd.overrides, notes);
    checkWritable(cmd.options.output);   // before minutes of rendering
    const Calibration cal = calibrate(scene, cmd.options, std::cout);
    scene.effects.indirect = cal.indirect;
    scene = scenePathsRelativeTo(scene, std::filesystem::absolute(cmd.options.output).parent_path().string());
    writeFileAtomically(cmd.options.output, jsonText(sceneToJson(scene), 2) + "\n");
    const std::string reference = cmd.options.truth ? "" : "reference " + secondsText(cal.truth_seconds) + ", ";
    char line[300];
    std::snprintf(line, sizeof line, "calibrated at %dx%d: RMSE %.4g -> %.4g (%sfit %s over %d marches); wrote %s\n",
                  cal.width, cal.height, cal.rmse_before, cal.rmse_after, reference.c_str(),
                  secondsText(cal.fit_seconds).c_str(), cal.marches, cmd.options.output.c_str());
    std::cout << line;
    printNotes(notes);
    return 0;
}

int runScene(const SceneCommand& cmd) {
    std::vector<std::string> notes;
    Scene scene = sceneFor(cmd.input, cmd.overrides, notes);
    if (!scene.camera) scene.camera = frameVolumeCamera(scene.volume().path, scene);
    // The image is named after the cache (#### kept), in the folder the render runs in.
    if (scene.output.path.empty()) scene.output.path = std::filesystem::path(cmd.input).stem().string() + ".exr";
    // The volume path as the scene file's reader resolves it: relative to the file's folder when
    // it was given relative, or absolute when it was given so or the scene goes to standard output
    // and may be saved anywhere.
    const std::filesystem::path volume = std::filesystem::absolute(scene.volume().path).lexically_normal();
    const bool given_absolute = std::filesystem::path(scene.volume().path).is_absolute();
    if (cmd.output) {
        scene = scenePathsRelativeTo(scene, std::filesystem::absolute(*cmd.output).parent_path().string());
        if (given_absolute) scene.volume().path = volume.string();
        writeFileAtomically(*cmd.output, jsonText(sceneToJson(scene), 2) + "\n");
        std::cout << "wrote " << *cmd.output << "\n";
    } else {
        scene.volume().path = volume.string();
        std::cout << jsonText(sceneToJson(scene), 2) << "\n";
    }
    printNotes(notes);
    return 0;
}

int runView(const ViewCommand& cmd) {
#if VOXLUX_HAS_VIEWER
    std::vector<std::string> notes;
    const Scene scene = sceneFor(cmd.input, cmd.overrides, notes);
    printNotes(notes);
    ViewerOptions options;
    options.source = cmd.input;
    options.script = cmd.script;
    options.bench = cmd.bench;
    options.frame_cache_mb = cmd.frame_cache_mb;
    return runViewer(scene, options);
#else
    throw InputError("voxlux view: this build has no viewer (configured with VOXLUX_VIEWER=OFF)");
#endif
}

int runInfo(const std::string& vdb, bool json) {
    const auto grids = summarizeFile(vdb);
    const auto triple = [](auto v) { return nlohmann::json::array({v[0], v[1], v[2]}); };
    if (json) {
        nlohmann::json out = {{"file", vdb}, {"grids", nlohmann::json::array()}};
        for (const auto& g : grids) {
            nlohmann::json gj = {{"name", g.name}, {"index", g.index}, {"type", g.value_type}, {"class", g.grid_class},
                                 {"active_voxels", g.active_voxels}, {"active_tiles", g.active_tiles},
                                 {"voxel_size", triple(g.voxel_size)}, {"bricks", g.bricks},
                                 {"brick_bytes", g.brick_bytes}, {"up", signedAxisName(g.up.frame[1])},
                                 {"front", signedAxisName(g.up.frame[2])}, {"up_reason", g.up.reason}};
            if (g.active_voxels > 0) {
                gj["bbox_min"] = triple(g.bbox.min());
                gj["bbox_max"] = triple(g.bbox.max());
                gj["world_min"] = triple(g.world_min);
                gj["world_max"] = triple(g.world_max);
            }
            if (g.has_range) gj[g.vector ? "length_range" : "value_range"] = {g.min_value, g.max_value};
            if (!g.damaged_metadata.empty()) gj["damaged_metadata"] = g.damaged_metadata;
            out["grids"].push_back(gj);
        }
        std::cout << jsonText(out, 2) << "\n";
        return 0;
    }
    std::cout << vdb << ": " << grids.size() << (grids.size() == 1 ? " grid\n" : " grids\n");
    for (const auto& g : grids) {
        std::cout << "  " << g.name << (g.index > 0 ? " (index " + std::to_string(g.index) + ")" : "") << "  " << g.value_type
                  << "  " << g.grid_class << "\n"
                  << "    active voxels " << g.active_voxels << " (" << g.active_tiles << " active tiles)\n";
        if (!g.damaged_metadata.empty()) std::cout << "    damaged metadata: " << g.damaged_metadata << "\n";
        if (g.active_voxels == 0) {
            std::cout << "    empty\n";
            continue;
        }
        const auto& b = g.bbox;
        std::cout << "    bbox (index) [" << b.min().x() << ", " << b.min().y() << ", " << b.min().z() << "] -> ["
                  << b.max().x() << ", " << b.max().y() << ", " << b.max().z() << "]  (" << b.dim().x() << " x "
                  << b.dim().y() << " x " << b.dim().z() << ")\n"
                  << "    bbox (world) [" << g.world_min.x << ", " << g.world_min.y << ", " << g.world_min.z << "] -> ["
                  << g.world_max.x << ", " << g.world_max.y << ", " << g.world_max.z << "]\n"
                  << "    voxel size " << g.voxel_size.x() << " " << g.voxel_size.y() << " " << g.voxel_size.z() << "\n";
        if (g.has_range) std::cout << (g.vector ? "    length range " : "    value range ") << g.min_value << " .. " << g.max_value << "\n";
        std::cout << "    bricks (8^3) " << g.bricks << ", " << bytesText(g.brick_bytes) << " in the atlas per channel\n"
                  << "    up axis " << g.up.reason << "\n";
    }
    return 0;
}

int runImport(const ImportCommand& cmd) {
    ImportOptions options;
    options.grid_name = cmd.name;
    options.background = cmd.background;
    options.up = cmd.up;
    options.front = cmd.front;
    if (!cmd.dims.empty()) {
        RawLayout raw;
        raw.dims = {cmd.dims[0], cmd.dims[1], cmd.dims[2]};
        if (!cmd.type) throw InputError(cmd.input + ": a raw volume needs --type (u8, u16, i16 or f32) beside --dims");
        const auto type = rawTypeNamed(*cmd.type);
        if (!type) throw InputError(cmd.input + ": --type '" + *cmd.type + "' is not a voxel type voxlux imports (u8, u16, i16 or f32)");
        raw.type = *type;
        if (!cmd.spacing.empty()) raw.spacing = {cmd.spacing[0], cmd.spacing[1], cmd.spacing[2]};
        raw.header_bytes = cmd.header_bytes.value_or(0);
        raw.big_endian = cmd.endian.value_or("little") == "big";
        options.raw = raw;
    } else if (cmd.type || !cmd.spacing.empty() || cmd.header_bytes || cmd.endian) {
        throw InputError(cmd.input + ": --type, --spacing, --header-bytes and --endian describe a raw file, and need --dims X,Y,Z");
    }
    const ImportReport r = importScan(cmd.input, cmd.output, options);
    const glm::ivec3 d = r.info.dims;
    const glm::dvec3 edge(glm::length(glm::dvec3(r.info.index_to_world[0])), glm::length(glm::dvec3(r.info.index_to_world[1])),
                          glm::length(glm::dvec3(r.info.index_to_world[2])));
    std::cout << cmd.input << ": " << r.info.format << (r.info.modality.empty() ? "" : " " + r.info.modality) << ", " << d.x << " x "
              << d.y << " x " << d.z << " voxels of " << edge.x << " x " << edge.y << " x " << edge.z << ", values " << r.min_value
              << " .. " << r.max_value << (r.info.units.empty() ? "" : " " + r.info.units) << "\n";
    if (r.non_finite > 0) std::cout << "  " << r.non_finite << " NaN or infinite voxels left inactive\n";
    if (!r.skipped_files.empty()) {
        std::cout << "  skipped " << r.skipped_files.size()
                  << (r.skipped_files.size() == 1 ? " file that is not a DICOM slice:" : " files that are not DICOM slices:");
        for (const auto& f : r.skipped_files) std::cout << " " << f;
        std::cout << "\n";
    }
    std::cout << "wrote " << cmd.output << ": grid '" << cmd.name << "', " << r.active_voxels << " of " << r.voxels
              << " voxels above the background " << r.background << " are active\n";
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

int runMakeSky(const std::string& output, SkyParams params, const std::string& resolution) {
    int width = 0, height = 0;
    char tail = 0;
    if (std::sscanf(resolution.c_str(), "%dx%d%c", &width, &height, &tail) != 2 || height < 2 || height > 8192 || width != 2 * height)
        throw InputError("--res: '" + resolution + "' is not WIDTHxHEIGHT with the width twice the height (2 to 8192 rows)");
    params.width = width;
    params.height = height;
    const ColorPipeline working = resolveWorkingSpace(ColorSettings{});
    const glm::mat3 xyz_to_working = working.xyz_to_working.value_or(kXyzD65ToAcescg);
    const std::vector<glm::vec3> sky = makeSky(params);
    RenderImage image;
    image.width = width;
    image.height = height;
    image.pixels.resize(sky.size());
    for (size_t i = 0; i < sky.size(); ++i) image.pixels[i].rgba = glm::vec4(glm::max(xyz_to_working * sky[i], glm::vec3(0.0f)), 1.0f);
    OutputSpec spec;
    spec.pixel_type = PixelType::Float;
    ExrMetadata meta;
    meta.color_space = working.working_space;
    writeExr(output, image, spec, meta);
    const glm::vec3 sun = sunDirection(params);
    std::cout << "wrote " << output << " (" << width << "x" << height << ", " << working.working_space << ", "
              << (params.kind == SkyKind::Overcast ? std::string("overcast")
                                                   : std::string(params.sun_disc ? "sun" : "no sun disc, sun") + " at " +
                                                         std::to_string(int(std::lround(params.sun_elevation))) + " degrees, toward (" +
                                                         std::to_string(sun.x).substr(0, 5) + ", " + std::to_string(sun.y).substr(0, 5) + ", " +
                                                         std::to_string(sun.z).substr(0, 5) + ") with up z")
              << ")\n";
    return 0;
}

}  // namespace voxlux
