#include "viewer/viewer_state.h"

#include <algorithm>

#include "viewer/orbit_camera.h"

namespace voxlux {

void ViewerState::showFrame(int f) {
    frame = std::clamp(f, first_frame, last_frame);
    submitted_version = ~uint64_t(0);   // the frame is not part of the scene: submit again
}

Camera ViewerState::camera() const {
    const glm::vec3 pivot = 0.5f * (bounds_lo + bounds_hi);
    if (editor.scene().camera) return lookAtForm(*editor.scene().camera, pivot);
    if (render)
        if (const auto frame = render->latest()) return lookAtForm(frame->camera, pivot);
    return Camera{};
}

}  // namespace voxlux
