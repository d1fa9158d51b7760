// voxlux command line: render, scene, study, info, import, make-cloud, make-sky. Errors are one line on stderr.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>

#include "tools/commands.h"
#include "tools/farm/process.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/thread_limit.h"
#include "scene/scene.h"

namespace {

void addSceneOverrides(CLI::App& cmd, voxlux::SceneOverrides& o) {
    cmd.add_option("--grid", o.grid, "density grid name (volume.density)");
    cmd.add_option("--grid-index", o.grid_index, "which of several grids with that name (volume.density.index)");
    cmd.add_option("--emission-grid", o.emission_grid, "emission of value x white from this grid, e.g. flame (emission)");
    cmd.add_option("--blackbody-grid", o.blackbody_grid,
                   "blackbody emission from a Mantaflow temperature grid, value x 1000 K (emission)");
    cmd.add_option("--color-grid", o.color_grid, "vec3 colour grid, e.g. Cd (volume.color)");
    cmd.add_option("--level-set", o.level_set, "reject|fog: convert a level set to fog (volume.level_set)");
    cmd.add_option("--up", o.up, "x|y|z|auto: the cache's up axis (volume.up; auto: as the file says)");
    cmd.add_option("--frame-on", o.frame_on,
                   "frame the camera on this frame of a sequence alone, and read the quick form's choices from it "
                   "(default: every frame on disk framed together, choices from the fullest)");
    cmd.add_option("--res", o.resolution, "WIDTHxHEIGHT (render.resolution)");
    cmd.add_option("--step", o.step, "march step in voxels (render.step)");
    cmd.add_option("--filter", o.filter, "trilinear|tricubic: reconstruction between voxels (render.filter)");
    cmd.add_option("--shadow-step", o.shadow_step, "shadow-ray step in voxels (render.shadow_step)");
    cmd.add_option("--density-scale", o.density_scale, "density to extinction (material.density_scale)");
    cmd.add_option("--light", o.lights,
                   "TYPE:key=value:... e.g. directional:dir=1,-1,0:intensity=3 (repeatable, replaces lights)");
    std::string shadows;   // the march's own and the lighting methods' values
    for (const std::string& name : voxlux::kShadowMethodNames) shadows += (shadows.empty() ? "" : "|") + name;
    cmd.add_option("--shadows", o.shadows, shadows + " (effects.shadows)");
    cmd.add_option("--quality", o.quality,
                   "draft|preview|final: method and knobs from the measured Pareto front (docs/accuracy.md); "
                   "other options override it");
    cmd.add_option("--set", o.sets, "KEY=VALUE: set any scene key, e.g. effects.cone.samples=50 (repeatable)");
    cmd.add_option("--backend", o.backend, "auto|cpu|gl (render.backend)");
    cmd.add_option("--method", o.method, "march|reference: Monte Carlo reference on the CPU (render.method)");
    cmd.add_option("--spp", o.spp, "reference samples per pixel (render.reference.spp)");
    cmd.add_option("--frames", o.frames, "FIRST-LAST[xSTEP] or a list, e.g. 1-240x2,300, for a #### volume path (volume.frames)");
    cmd.add_option("--pixel-type", o.pixel_type, "half|float (output.pixel_type)");
    cmd.add_flag("--deep", o.deep, "also write a deep EXR, NAME.deep.exr: RGBA, Z, ZBack samples (output.deep)");
    cmd.add_option("--aovs", o.aovs, "direct,ambient,indirect,emission,transmittance,depth,variance (output.aovs)")->delimiter(',');
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"voxlux: volume shading for OpenVDB caches"};
    app.require_subcommand(1);
    app.set_version_flag("--version", VOXLUX_VERSION);

    voxlux::RenderCommand render;
    auto* renderCmd = app.add_subcommand("render", "render a scene .json, or a .vdb with default framing");
    renderCmd->add_option("input", render.input, "scene .json or volume .vdb")->required();
    renderCmd->add_option("-o,--output", render.overrides.output, "output .exr (output.path)");
    renderCmd->add_option("--preview", render.overrides.preview,
                          "also write an 8-bit PNG through the display and view (output.preview; #### for frames)");
    renderCmd->add_flag("--explain", render.explain, "print the render graph (stages, why each runs, what each reads) and exit");
    renderCmd->add_option("--stats", render.sequence.stats, "write per-stage times and peak memory as JSON");
    renderCmd->add_flag("--resume", render.sequence.resume,
                        "skip frames whose EXR is whole and was rendered from this scene (voxlux/sceneHash); docs/farm.md");
    renderCmd->add_flag("--fail-fast", render.sequence.fail_fast,
                        "stop at the first frame that fails (default: render the others, exit 3 naming the failed frames)");
    renderCmd->add_option("--log-json", render.sequence.log_json,
                          "append one JSON line per frame to this file: status, seconds, stages, warnings, error");
    renderCmd->add_option("--light-edit", render.light_edits,
                          "EDITS.json: replay light edits (selective updates), print each one's time, write the last frame");
    addSceneOverrides(*renderCmd, render.overrides);

    voxlux::SceneCommand scene;
    auto* sceneCmd = app.add_subcommand("scene", "write the scene the quick form of render would use, to edit");
    sceneCmd->add_option("volume", scene.input, "volume .vdb (#### with --frames)")->required();
    sceneCmd->add_option("-o,--output", scene.output,
                         "write the scene to this .json (volume path relative to it) instead of standard output");
    sceneCmd->add_option("--image", scene.overrides.output, "output.path to put in the scene (default: the cache's name, .exr)");
    sceneCmd->add_option("--preview", scene.overrides.preview, "output.preview to put in the scene");
    addSceneOverrides(*sceneCmd, scene.overrides);

    std::string infoInput;
    bool infoJson = false;
    auto* infoCmd = app.add_subcommand("info", "list the grids of a .vdb file");
    infoCmd->add_option("volume", infoInput, "volume .vdb")->required();
    infoCmd->add_flag("--json", infoJson, "print JSON for pipeline tools");

    voxlux::ImportCommand import;
    auto* importCmd = app.add_subcommand("import", "convert a scan (DICOM folder, NIfTI, VolPack .den, raw) to a sparse .vdb (docs/scans.md)");
    importCmd->add_option("input", import.input, "DICOM series folder, .nii/.nii.gz, .den, or a raw file with --dims and --type")->required();
    importCmd->add_option("-o,--output", import.output, "output .vdb")->required();
    importCmd->add_option("--name", import.name, "the grid's name")->capture_default_str();
    importCmd->add_option("--background", import.background, "voxels at or below this value are inactive (default: the scan's minimum)");
    importCmd->add_option("--dims", import.dims, "raw: voxels along x,y,z (x fastest)")->delimiter(',')->expected(3);
    importCmd->add_option("--type", import.type, "raw: u8|u16|i16|f32");
    importCmd->add_option("--spacing", import.spacing, "raw: voxel edges along x,y,z (default 1,1,1)")->delimiter(',')->expected(3);
    importCmd->add_option("--header-bytes", import.header_bytes, "raw: bytes before the first voxel (default 0)");
    importCmd->add_option("--endian", import.endian, "raw: little|big (default little)")->check(CLI::IsMember({"little", "big"}));
    importCmd->add_option("--up", import.up, "the axis toward the head: x|y|z|-x|-y|-z (NIfTI and DICOM say z; raw and .den do not say)");
    importCmd->add_option("--front", import.front, "the axis toward the face, which the quick form's camera looks at (NIfTI and DICOM: y)");

    voxlux::StudyCommand study;
    auto* studyCmd = app.add_subcommand(
        "study", "render with every method and knob and the Monte Carlo reference; chart error against time");
    studyCmd->add_option("input", study.input, "scene .json or volume .vdb")->required();
    studyCmd->add_option("-o,--output", study.options.out_dir, "folder for study.csv, chart.svg, report.md, truth.exr")
        ->capture_default_str();
    studyCmd->add_option("--title", study.options.title, "the scene's name in the report and chart");
    studyCmd->add_option("--spp-list", study.options.spps, "reference samples per pixel to measure")
        ->delimiter(',')->capture_default_str();
    studyCmd->add_option("--truth-spp", study.options.truth_spp, "samples per pixel of the ground truth")->capture_default_str();
    studyCmd->add_option("--repeats", study.options.repeats, "renders per config, the fastest counts")
        ->check(CLI::Range(1, 100))->capture_default_str();
    studyCmd->add_flag("--fresh", study.options.fresh, "measure everything again instead of resuming");
    addSceneOverrides(*studyCmd, study.overrides);

    voxlux::CalibrateCommand calibrate;
    auto* calibrateCmd = app.add_subcommand(
        "calibrate", "fit the propagation method's indirect light to a Monte Carlo reference; write the calibrated scene");
    calibrateCmd->add_option("input", calibrate.input, "scene .json or volume .vdb")->required();
    calibrateCmd->add_option("-o,--output", calibrate.options.output, "the calibrated scene .json")->required();
    calibrateCmd->add_option("--truth", calibrate.options.truth, "fit this reference image (RGBA EXR, scene-linear) instead of rendering one");
    calibrateCmd->add_option("--reference-spp", calibrate.options.spp, "the reference's samples per pixel")
        ->check(CLI::Range(2, 1 << 20))->capture_default_str();
    calibrateCmd->add_option("--max-side", calibrate.options.max_side, "the fit's resolution: longest side in pixels")
        ->check(CLI::Range(8, 1 << 16))->capture_default_str();
    addSceneOverrides(*calibrateCmd, calibrate.overrides);

    voxlux::ViewCommand view;
    auto* viewCmd = app.add_subcommand("view", "open the interactive look-dev viewer on a scene .json or a .vdb (docs/viewer.md)");
    viewCmd->add_option("input", view.input, "scene .json or volume .vdb")->required();
    viewCmd->add_option("--script", view.script, "ACTIONS.json: replay UI actions (set keys, move lights, screenshots, save)");
    viewCmd->add_flag("--bench", view.bench, "time a light edit, a camera orbit and a material change, print the figures, quit");
    viewCmd->add_option("--frame-cache", view.frame_cache_mb, "MB for the grids and bricks of frames seen, so scrubbing back reads nothing")
        ->check(CLI::Range(size_t(0), size_t(1) << 20))->capture_default_str();
    addSceneOverrides(*viewCmd, view.overrides);

    auto* farmCmd = app.add_subcommand("farm", "render a sequence on a scheduler's farm in chunks that resume (docs/farm.md)");
    farmCmd->require_subcommand(1);
    voxlux::FarmSubmitCommand farmSubmit;
    auto* submitCmd = farmCmd->add_subcommand("submit", "write a job folder and submit the sequence's chunks as one job array");
    submitCmd->add_option("input", farmSubmit.input, "scene .json, or a #### .vdb")->required();
    submitCmd->add_option("--chunk", farmSubmit.options.chunk, "frames per task")->check(CLI::Range(int64_t(1), int64_t(1) << 31))
        ->capture_default_str();
    submitCmd->add_option("--job-dir", farmSubmit.options.job_dir, "the job folder (default: NAME.farm, after the input)");
    submitCmd->add_option("--scheduler", farmSubmit.options.scheduler, "slurm")->capture_default_str();
    submitCmd->add_option("--partition", farmSubmit.options.partition, "the scheduler's partition (queue); default: its own");
    submitCmd->add_option("--cpus", farmSubmit.options.cpus, "cores each task asks for (sbatch --cpus-per-task); default: the scheduler's")
        ->check(CLI::Range(1, 4096));
    submitCmd->add_flag("--dry-run", farmSubmit.options.dry_run, "write the job folder and script, print the submit command, submit nothing");
    submitCmd->add_flag("--wait", farmSubmit.options.wait, "wait for the job to end, then check its frames as collect does");
    submitCmd->add_option("-o,--output", farmSubmit.overrides.output, "output .exr with #### (output.path)");
    submitCmd->add_option("--preview", farmSubmit.overrides.preview, "also write 8-bit PNGs, #### (output.preview)");
    addSceneOverrides(*submitCmd, farmSubmit.overrides);
    std::string farmJobDir;
    auto* statusCmd = farmCmd->add_subcommand("status", "each chunk's state in the scheduler");
    statusCmd->add_option("job", farmJobDir, "the job folder")->required();
    voxlux::FarmCollectOptions collect;
    auto* collectCmd = farmCmd->add_subcommand("collect", "check every frame (whole EXR, this scene's hash); list what is missing");
    collectCmd->add_option("job", farmJobDir, "the job folder")->required();
    collectCmd->add_flag("--resubmit", collect.resubmit, "submit again the chunks with frames missing or corrupt");
    collectCmd->add_flag("--wait", collect.wait, "wait for queued and running tasks first, and for the resubmission");

    std::string cloudOutput;
    int cloudResolution = 96;
    unsigned cloudSeed = 1;
    auto* cloudCmd = app.add_subcommand("make-cloud", "write a procedural cloud .vdb");
    cloudCmd->add_option("-o,--output", cloudOutput, "output .vdb")->required();
    cloudCmd->add_option("--res", cloudResolution, "voxels across")->check(CLI::Range(8, 1024));
    cloudCmd->add_option("--seed", cloudSeed, "noise seed");

    std::string skyOutput, skyKind = "clear", skyResolution = "512x256";
    voxlux::SkyParams sky;
    std::optional<float> skyElevation, skyTurbidity;
    auto* skyCmd = app.add_subcommand("make-sky", "write a lat-long sky .exr for an environment light (docs/environment.md)");
    skyCmd->add_option("-o,--output", skyOutput, "output .exr")->required();
    skyCmd->add_option("--kind", skyKind, "clear (Preetham's sky and the sun), sunset (the same, the sun 3 degrees up), overcast (CIE)")
        ->check(CLI::IsMember({"clear", "sunset", "overcast"}));
    skyCmd->add_option("--sun-elevation", skyElevation, "degrees above the horizon (clear 35, sunset 3)")->check(CLI::Range(-90.0, 90.0));
    skyCmd->add_option("--sun-azimuth", sky.sun_azimuth, "degrees from the map's centre column towards its left quarter")->check(CLI::Range(-360.0, 360.0));
    skyCmd->add_option("--turbidity", skyTurbidity, "haze, 2 (very clear) to 10 (clear 3, sunset 5)")->check(CLI::Range(2.0, 10.0));
    skyCmd->add_option("--ground-albedo", sky.ground_albedo, "the ground's reflectance below the horizon")->check(CLI::Range(0.0, 1.0));
    skyCmd->add_option("--res", skyResolution, "WIDTHxHEIGHT, width twice the height");
    bool skyNoSun = false;
    skyCmd->add_flag("--no-sun", skyNoSun, "leave the sun's disc out (the sky it lights stays): for a scene whose sun is a directional light");

    std::optional<int> threads;   // --threads; ThreadLimit reads $VOXLUX_THREADS without it
    for (auto* cmd : {renderCmd, studyCmd, calibrateCmd, viewCmd, submitCmd})
        cmd->add_option("--threads", threads,
                        "cores to use (default: $VOXLUX_THREADS, else every core the process may run on; farm submit: "
                        "each task's, as --cpus)");

    double progressSeconds = 10.0;
    std::vector<CLI::Option*> progressFlags;
    for (auto* cmd : {renderCmd, studyCmd})
        progressFlags.push_back(cmd->add_flag("--progress{10}", progressSeconds,
                                              "print a progress line every 10 s (--progress=SECONDS) to stderr when it is not a "
                                              "terminal (a terminal gets a bar)")
                                    ->check(CLI::Range(0.01, 86400.0)));

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version exit 0 with their text; every malformed command line is bad input:
        // one line, exit 2, as any other.
        if (e.get_exit_code() == 0) return app.exit(e);
        // A word that is no command: name it and the commands, rather than CLI11's "A subcommand is required".
        std::string commands;
        bool known = false;
        for (const CLI::App* cmd : app.get_subcommands({})) {
            commands += (commands.empty() ? "" : ", ") + cmd->get_name();
            known = known || (argc > 1 && cmd->get_name() == argv[1]);
        }
        if (argc > 1 && argv[1][0] != '-' && !known) {
            std::cerr << "voxlux: error: command line: '" << argv[1] << "' is not a command (" << commands << ")\n";
            return voxlux::kInputError;
        }
        std::cerr << "voxlux: error: command line: " << e.what() << "\n";
        return voxlux::kInputError;
    }

    voxlux::installInterruptHandler();
    if (isatty(STDERR_FILENO)) voxlux::setProgressDisplay(voxlux::ProgressDisplay::Bar, std::cerr);
    else if (std::any_of(progressFlags.begin(), progressFlags.end(), [](const CLI::Option* o) { return o->count() > 0; }))
        voxlux::setProgressDisplay(voxlux::ProgressDisplay::Lines, std::cerr, progressSeconds);
    try {
        if (*submitCmd && farmSubmit.options.cpus == 0 && threads) farmSubmit.options.cpus = *threads;
        const voxlux::ThreadLimit limit(*submitCmd ? std::nullopt : threads);
        if (*renderCmd) return voxlux::runRender(render);
        if (*sceneCmd) return voxlux::runScene(scene);
        if (*studyCmd) {
            study.options.command = "voxlux";
            for (int i = 1; i < argc; ++i) study.options.command += " " + voxlux::shellQuoted(argv[i]);
            return voxlux::runStudyCommand(study);
        }
        if (*calibrateCmd) return voxlux::runCalibrateCommand(calibrate);
        if (*submitCmd) return voxlux::runFarmSubmit(farmSubmit);
        if (*statusCmd) return voxlux::farmStatus(farmJobDir, std::cout);
        if (*collectCmd) return voxlux::farmCollect(farmJobDir, collect, std::cout);
        if (*infoCmd) return voxlux::runInfo(infoInput, infoJson);
        if (*importCmd) return voxlux::runImport(import);
        if (*viewCmd) return voxlux::runView(view);
        if (*cloudCmd) return voxlux::runMakeCloud(cloudOutput, cloudResolution, cloudSeed);
        if (*skyCmd) {
            const bool sunset = skyKind == "sunset";
            sky.kind = skyKind == "overcast" ? voxlux::SkyKind::Overcast : voxlux::SkyKind::Clear;
            sky.sun_elevation = skyElevation.value_or(sunset ? 3.0f : 35.0f);
            sky.turbidity = skyTurbidity.value_or(sunset ? 5.0f : 3.0f);
            sky.sun_disc = !skyNoSun;
            return voxlux::runMakeSky(skyOutput, sky, skyResolution);
        }
    } catch (const voxlux::Interrupted&) {
        voxlux::clearProgressLine();
        std::cerr << "voxlux: interrupted: stopped before the next output; every file written is whole\n";
        return 128 + voxlux::interruptSignal();   // as a shell reports a process ended by it: 130 SIGINT, 143 SIGTERM
    } catch (const voxlux::InputError& e) {
        voxlux::clearProgressLine();
        std::cerr << "voxlux: error: " << e.what() << "\n";
        return voxlux::kInputError;
    } catch (const std::filesystem::filesystem_error& e) {
        // A path the user gave that the system refuses (too long, a file where a folder must be).
        std::cerr << "voxlux: error: " << e.path1().string() << ": " << e.code().message() << "\n";
        return voxlux::kInputError;
    } catch (const std::exception& e) {
        std::cerr << "voxlux: internal error: " << e.what() << "\n";
        return voxlux::kInternalError;
    }
    return 0;
}
