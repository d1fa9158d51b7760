// The command-line flags of `render`, `scene` and `study` that override scene keys (docs/cli.md),
// applied to a scene through its JSON so that every value gets the scene file's validation, and
// each error names the flag that brought the value.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

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
    bool deep = false;                          // output.deep
    std::optional<std::string> quality;         // draft|preview|final: applied before every other override
    std::vector<std::string> sets;              // "dotted.key=JSON value", any scene key
    std::optional<std::string> up;              // x|y|z|auto (volume.up)
    std::optional<std::string> filter;          // trilinear|tricubic (render.filter)
    std::optional<int> frame_on;                // not a key: the frame a sequence is framed on, and the quick
                                                // form's choices read (default: all frames; the middle one)
};

// `base` with the overrides applied: the quality preset first, then the flags, then each --set in
// order. Throws InputError "<flag>: <JSON pointer>: <problem>" for the first flag whose value the
// scene refuses.
Scene applyOverrides(const Scene& base, const SceneOverrides& overrides);

}  // namespace voxlux
