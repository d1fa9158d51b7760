// The viewport: the newest image drawn to fit the window (scaled up while coarse levels show),
// the before/after wipe, the pixel probe, the volumes' bounding box and an axis triad, the light
// gizmos, each volume's gizmo (W moves, E turns, R scales it, as in Maya), and the camera moves of the mouse as Houdini's and Blender's viewports have them (left
// drag orbits, middle pans, right or the wheel dollies, with or without Alt; F frames the volume;
// Ctrl + left drag draws a render region, rendered alone at full quality over the image; Shift +
// right drag turns the environment map about its up, as Substance Painter and Marmoset do).
// Everything is drawn with Dear ImGui's background draw list, clipped to the viewport, so the
// panels always cover it; one texture per image.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "viewer/aov_display.h"
#include "viewer/viewer_state.h"

namespace voxlux {

class Viewport {
public:
    Viewport();
    ~Viewport();
    Viewport(const Viewport&) = delete;
    Viewport& operator=(const Viewport&) = delete;

    // Draws into the screen rectangle [lo, hi) and handles the mouse and keys over it.
    void draw(ViewerState& state, glm::vec2 lo, glm::vec2 hi);

    // Where the image sits on screen, as last drawn.
    glm::vec2 imageLo() const { return image_lo_; }
    glm::vec2 imageHi() const { return image_hi_; }
    // The scene-linear value under the mouse, if it is over the image.
    const std::optional<glm::vec4>& probe() const { return probe_; }
    glm::ivec2 probePixel() const { return probe_pixel_; }

    // The light gizmo drag of `light` by `by` screen pixels, as a mouse drag does it.
    static bool dragLight(ViewerState& state, int light, glm::vec2 by, glm::vec2 image_size);
    // The gizmo drag of volume `index` by `by` screen pixels in state.volume_gizmo's mode; false
    // when the edit was refused or the volume is placed by a matrix or keys.
    static bool dragVolume(ViewerState& state, int index, glm::vec2 by, glm::vec2 image_size);

private:
    struct Texture;
    void upload(const ViewerState& state, Texture& texture, const ViewFrame& frame);
    void gizmos(ViewerState& state, glm::vec2 lo, glm::vec2 hi);
    void guides(const ViewerState& state);
    void mouse(ViewerState& state, glm::vec2 lo, glm::vec2 hi);
    void region(ViewerState& state);

    std::unique_ptr<Texture> current_, held_, backdrop_;
    AovDisplay aov_display_;
    glm::vec2 image_lo_{0.0f}, image_hi_{1.0f};
    std::optional<glm::vec4> probe_;
    glm::ivec2 probe_pixel_{0};
    int dragging_light_ = -1;
    int dragging_volume_ = -1;
    bool navigating_[3] = {false, false, false};   // the drag of each button began in the viewport
    std::optional<glm::vec2> region_from_;          // where a Ctrl + drag of the render region began
};

}  // namespace voxlux
