// The viewer's Dear ImGui panels, grouped as the scene file is: the scene panel (lights, method
// and quality, colour, volume, and every other key of the scene as a tree), the image panel (AOV,
// wipe, probe, progress, what the last edit re-ran) and the timeline of a sequence. Each edit goes
// through the SceneEditor; actions that write files come back to the caller.
#pragma once
#include <string>

#include "viewer/environment_thumbnail.h"
#include "viewer/viewer_state.h"
#include "viewer/viewport.h"

namespace voxlux {

struct PanelRequests {
    bool save = false;     // "Save scene" pressed (to state.save_path)
    bool render = false;   // "Render" pressed (to the scene's output path)
};

// `thumbnail` draws the selected environment light's map.
PanelRequests drawScenePanel(ViewerState& state, EnvironmentThumbnailWidget& thumbnail, float x, float width, float height);
void drawImagePanel(ViewerState& state, const Viewport& viewport, float x, float width, float height);
void drawTimeline(ViewerState& state, float x, float y, float width);

}  // namespace voxlux
