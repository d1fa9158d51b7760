// `voxlux view`: the interactive look-dev viewer. A GLFW window (OpenGL 3.3 core) with Dear ImGui
// panels around the viewport; renders run on the ProgressiveRender worker through the render
// graph of `voxlux render`, so the UI loop only draws, and a scene saved here renders the same
// with `voxlux render`. docs/viewer.md describes the controls.
#pragma once
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

struct ViewerOptions {
    std::string source;                       // the scene file or cache, for the title and the save path
    std::optional<std::string> script;        // --script: actions to replay (view_script.h)
    bool bench = false;                       // --bench: time edits and print the figures
    size_t frame_cache_mb = 2048;             // --frame-cache: memory for the grids and bricks of frames seen
    glm::ivec2 window{1600, 900};
};

// Runs until the window closes or a script quits. Throws InputError when no display can be opened
// or the script is bad, before the window opens.
int runViewer(const Scene& scene, const ViewerOptions& options);

}  // namespace voxlux
