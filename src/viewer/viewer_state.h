// What the viewer's parts share: the edited scene, the progressive render, the volumes' boxes,
// and the display choices that are the viewer's own (not the scene's): the AOV shown, the wipe,
// the selected light and volume, the volume gizmo's mode, the frame of a sequence.
#pragma once
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "viewer/progressive_render.h"
#include "viewer/scene_editor.h"
#include "viewer/volume_gizmo.h"

namespace voxlux {

// The AOVs the viewport can show; "beauty" is the graded image through the scene's display and view.
inline const std::vector<std::string> kViewAovs = {"beauty", "direct", "indirect", "ambient", "emission", "transmittance", "depth"};

struct ViewerState {
    explicit ViewerState(Scene scene) : editor(std::move(scene)) {}

    SceneEditor editor;
    std::unique_ptr<ProgressiveRender> render;
    uint64_t submitted_version = ~uint64_t(0);   // the editor version last handed to the render
    uint64_t submitted_edit = 0;                 // the render's number for that submit
    std::optional<int> submitted_frame;          // and the frame
    uint64_t failure_seen = 0;                   // the newest failed edit already shown
    std::string message;                         // the line under the viewport: an error, or what was written
    bool message_is_error = false;

    glm::vec3 bounds_lo{-1.0f}, bounds_hi{1.0f};   // the enabled volumes' world box (framing, gizmo sizes)
    // Each volume's box in its file's world (its density grid's active voxels) at the frame shown,
    // by index; unset when its file could not be read (the render names the problem).
    std::vector<std::optional<std::array<glm::vec3, 2>>> volume_boxes;
    std::string volume_boxes_key;                  // the frame, paths and grids they were read for
    std::optional<int> frame;                      // the frame of a #### sequence shown
    int first_frame = 0, last_frame = 0;
    bool playing = false;
    // The converged image of each frame seen since the last edit (display texels only: 4 bytes a
    // pixel), so playback runs through them at the sequence's fps, as a flipbook; an edit empties it.
    std::map<int, std::shared_ptr<const ViewFrame>> flipbook;
    size_t flipbook_bytes = 0;
    uint64_t flipbook_version = 0;
    size_t frame_cache_bytes = 0;                  // the budget of the frame cache (--frame-cache)

    // The render region (Ctrl+drag in the viewport): the render marches only these fractions of the
    // image, at full quality, over `backdrop`, the image shown when it was drawn. The viewer's own,
    // not the scene's: a saved scene and the Render button render the whole image.
    std::optional<std::array<float, 4>> region;
    std::shared_ptr<const ViewFrame> backdrop;
    std::optional<std::array<float, 4>> submitted_region;
    // The scene the progressive render is given: the edited scene with the viewer's region.
    Scene renderedScene() const;

    std::string aov = "beauty";
    bool show_guides = true;           // the bounding box and the axis triad
    int selected_light = 0;
    int selected_volume = -1;          // its box is drawn and its gizmo handle highlighted
    VolumeGizmo volume_gizmo = VolumeGizmo::Move;
    bool wipe = false;                 // show the held image left of the wipe line
    float wipe_at = 0.5f;              // fraction of the viewport's width
    std::shared_ptr<const ViewFrame> held;   // the "before" image of the wipe

    std::map<std::string, glm::vec4> widgets;   // named widgets' screen rectangles (lo, hi), for `layout`
    std::string save_path;             // where "Save scene" writes
    std::string output_path;           // the Render panel's output field, as typed
    bool output_typing = false;        // the field has the keyboard: the scene's path does not overwrite it

    double ui_fps = 0.0;               // smoothed frame rate of the UI loop
    double slowest_ui_frame = 0.0;     // seconds, since the last reset (benchmarks)

    // Shows frame `f` of the sequence (clamped to its range): the render is asked for it, unless
    // playback runs through the flipbook.
    void showFrame(int f);
    // The image to show: the render's newest, or the flipbook's of `frame` while the render has
    // none of that frame.
    std::shared_ptr<const ViewFrame> image() const;
    // Keeps `f` in the flipbook when it is the converged image of the newest submit, within the
    // frame cache's budget. emptyFlipbook: after an edit, which makes every image in it stale.
    void remember(const std::shared_ptr<const ViewFrame>& f);
    void emptyFlipbook();
    // The sequence's frames a second: render.motion_blur.fps, whose default (24) stands without it.
    double fps() const;
    // The scene's camera, or the framing the render chose when it has none yet.
    Camera camera() const;
    // Volume `index`'s box centre as its transform places it: where its gizmo handle sits and what
    // the gizmo turns and scales about. Unset without a box, or when the gizmo cannot edit its
    // placement: a matrix, keys, or instances (each placed on top of the transform, so none sits
    // where the handle would).
    std::optional<glm::vec3> volumePivot(size_t index) const;
    // The environment light a Shift + right drag turns: the selected light if it is one, else the
    // first enabled one; -1 without any.
    int environmentLight() const;
    // Reads volume_boxes again when the frame or a volume's file or grid changed.
    void readVolumeBoxes();
    // The world box of every enabled volume as placed (instances too), from volume_boxes.
    void updateBounds();
    void showError(const std::string& line) { message = line, message_is_error = true; }
    void showNote(const std::string& line) { message = line, message_is_error = false; }
};

}  // namespace voxlux
