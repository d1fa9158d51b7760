// The quick form, `voxlux render cache.vdb` (and `voxlux scene cache.vdb`): a scene from a cache
// alone, with what the user did not set chosen from the data of one reference frame:
// - the up axis, from the file (volume/up_axis.h), which orients the key light;
// - density in voxel units, scaled so that the median column of the volume along the view holds
//   an optical depth of kQuickOpticalDepth, whatever the cache's scale or density range;
// - blackbody emission scaled so that 99% of the columns along the view emit at most 1 (before
//   absorption), so a fire does not clip.
// Costs one more read of the reference frame's density and emission grids, and a pass over their
// active values.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "tools/scene_overrides.h"

namespace voxlux {

inline constexpr float kQuickOpticalDepth = 2.0f;

// The scene of the quick form before any flag: the cache and the defaults.
Scene quickScene(const std::string& vdb);

// `scene` (quickScene with `overrides` applied) with the choices above made for the keys the
// overrides leave unset, read from `frame` of a sequence (default: the middle of volume.frames).
// Each choice is described in `notes`, one line each.
Scene completeQuickScene(Scene scene, const SceneOverrides& overrides, std::optional<int> frame,
                         std::vector<std::string>& notes);

}  // namespace voxlux
