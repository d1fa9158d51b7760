// What a drag of a volume's gizmo does (W, E and R, as in Maya): move it in the plane facing the
// camera, turn it about the camera's up and right axes, or scale it, all about its box's centre.
// The viewport draws and drags it (viewport.h); a view script names the mode (view_script.h).
#pragma once
#include <string>
#include <vector>

namespace voxlux {

enum class VolumeGizmo { Move, Rotate, Scale };
inline const std::vector<std::string> kVolumeGizmoNames{"move", "rotate", "scale"};

}  // namespace voxlux
