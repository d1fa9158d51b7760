// The voxlux subcommands. Each returns the process exit code; InputError escapes to main().
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "tools/study.h"

namespace voxlux {

// Options of `render` and `scene` that override scene keys one to one (docs/cli.md).
struct SceneOverrides {
    std::optional<std::string> grid, color_grid;
    std::optional<std::string> emission_grid, blackbody_grid;  // emission sources: replace the scene's
    std::optional<int> grid_index;
    std::optional<std::string> level_set;
    std::optional<std::string> resolution;      // "WxH"
    std::optional<float> step, shadow_step, density_scale;
    std::vector<std::string> lights;            // "TYPE:key=value:..."
    std::optional<std::string> shadows, backend, frames, pixel_type;
    std::optional<std::string> method;          // render.method
    std::optional<int> spp;                     // render.reference.spp
    std::optional<std::vector<std::string>> aovs;
    std::optional<std::string> output, preview;
    std::optional<std::string> quality;         // draft|preview|final: applied before every other override
    std::vector<std::string> sets;              // "dotted.key=JSON value", any scene key
};

struct RenderCommand {
    std::string input;                          // scene .json, or a .vdb for the quick form
    SceneOverrides overrides;
    bool explain = false;
    std::optional<std::string> stats;
    std::optional<std::string> light_edits;     // replay these light edits, then write the final frame
};

struct StudyCommand {
    std::string input;                          // scene .json, or a .vdb for the quick form
    SceneOverrides overrides;
    StudyOptions options;
};

int runRender(const RenderCommand& cmd);
int runStudyCommand(const StudyCommand& cmd);
int runScene(const std::string& vdb, const SceneOverrides& overrides);
int runInfo(const std::string& vdb, bool json);
int runMakeCloud(const std::string& output, int resolution, unsigned seed);

}  // namespace voxlux
