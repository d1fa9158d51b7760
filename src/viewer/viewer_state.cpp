#include "viewer/viewer_state.h"

#include "viewer/orbit_camera.h"

namespace voxlux {

Camera ViewerState::camera() const {
    const glm::vec3 pivot = 0.5f * (bounds_lo + bounds_hi);
    if (editor.scene().camera) return lookAtForm(*editor.scene().camera, pivot);
    if (render)
        if (const auto frame = render->latest()) return lookAtForm(frame->camera, pivot);
    return Camera{};
}

}  // namespace voxlux
