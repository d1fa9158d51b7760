// The voxlux subcommands. Each returns the process exit code; InputError escapes to main().
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "optics/sky_model.h"
#include "tools/scene_overrides.h"
#include "tools/calibrate.h"
#include "tools/farm/farm_commands.h"
#include "tools/sequence_render.h"
#include "tools/study.h"

namespace voxlux {

struct RenderCommand {
    std::string input;                          // scene .json, or a .vdb for the quick form
    SceneOverrides overrides;
    bool explain = false;
    SequenceOptions sequence;                   // --resume, --fail-fast, --log-json, --stats
    std::optional<std::string> light_edits;     // replay these light edits, then write the final frame
};

struct StudyCommand {
    std::string input;                          // scene .json, or a .vdb for the quick form
    SceneOverrides overrides;
    StudyOptions options;
};

struct CalibrateCommand {
    std::string input;                          // scene .json, or a .vdb for the quick form
    SceneOverrides overrides;
    CalibrateOptions options;
};

int runRender(const RenderCommand& cmd);
int runStudyCommand(const StudyCommand& cmd);
int runCalibrateCommand(const CalibrateCommand& cmd);
struct SceneCommand {
    std::string input;                          // volume .vdb (#### with --frames)
    SceneOverrides overrides;
    std::optional<std::string> output;          // write the scene here, else to standard output
};

int runScene(const SceneCommand& cmd);

struct FarmSubmitCommand {
    std::string input;                          // scene .json, or a #### .vdb for the quick form
    SceneOverrides overrides;
    FarmSubmitOptions options;
};

int runFarmSubmit(const FarmSubmitCommand& cmd);

struct ViewCommand {
    std::string input;                          // scene .json, or a .vdb for the quick form
    SceneOverrides overrides;
    std::optional<std::string> script;          // replay these UI actions
    bool bench = false;
    size_t frame_cache_mb = 2048;
};

// `voxlux view`; in a build without the viewer, an error saying so.
int runView(const ViewCommand& cmd);
int runInfo(const std::string& vdb, bool json);
// voxlux import: a scan to a sparse .vdb (src/scan/scan_import.h). The raw layout's flags are
// kept as given, so that one given without --dims can be refused by name.
struct ImportCommand {
    std::string input, output;
    std::string name = "density";
    std::optional<float> background;
    std::vector<int> dims;
    std::optional<std::string> type, endian;
    std::vector<double> spacing;
    std::optional<std::uint64_t> header_bytes;
    std::optional<std::string> up, front;   // the axes toward the head and the face
};
int runImport(const ImportCommand& cmd);
int runMakeCloud(const std::string& output, int resolution, unsigned seed);
// Writes `params`' sky at `resolution` ("WIDTHxHEIGHT", width twice the height) as a float EXR in
// the working space of the default colour config (docs/environment.md).
int runMakeSky(const std::string& output, SkyParams params, const std::string& resolution);

}  // namespace voxlux
