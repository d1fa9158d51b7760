#include "viewer/viewer_state.h"

#include <algorithm>
#include <limits>

#include "core/frame_pattern.h"
#include "scene/camera_file.h"
#include "viewer/orbit_camera.h"
#include "volume/vdb_loader.h"

namespace voxlux {

void ViewerState::showFrame(int f) { frame = std::clamp(f, first_frame, last_frame); }

std::shared_ptr<const ViewFrame> ViewerState::image() const {
    std::shared_ptr<const ViewFrame> latest = render ? render->latest() : nullptr;
    if (frame && (!latest || latest->frame != frame))
        if (const auto kept = flipbook.find(*frame); kept != flipbook.end()) return kept->second;
    return latest;
}

void ViewerState::emptyFlipbook() {
    flipbook.clear();
    flipbook_bytes = 0;
    flipbook_version = editor.version();
}

void ViewerState::remember(const std::shared_ptr<const ViewFrame>& f) {
    if (!f || !f->converged || !f->frame || f->edit != submitted_edit || flipbook.count(*f->frame) || region) return;
    if (flipbook_bytes + f->display_texels.size() > frame_cache_bytes) return;
    auto slim = std::make_shared<ViewFrame>();
    slim->edit = f->edit;
    slim->converged = true;
    slim->frame = f->frame;
    slim->camera = f->camera;
    slim->image.width = f->image.width;
    slim->image.height = f->image.height;
    slim->display_texels = f->display_texels;
    flipbook_bytes += slim->display_texels.size();
    flipbook[*f->frame] = std::move(slim);
}

Scene ViewerState::renderedScene() const {
    Scene s = editor.scene();
    if (region) s.render.region = region;
    return s;
}

double ViewerState::fps() const {
    const auto& blur = editor.scene().render.motion_blur;
    return double(blur ? blur->fps : MotionBlur{}.fps);
}

std::optional<glm::vec3> ViewerState::volumePivot(size_t index) const {
    const std::vector<VolumeSpec>& volumes = editor.scene().volumes;
    if (index >= volume_boxes.size() || !volume_boxes[index] || index >= volumes.size()) return std::nullopt;
    const VolumeSpec& v = volumes[index];
    if (!v.instances.empty() || (v.transform && (v.transform->matrix || !v.transform->keys.empty()))) return std::nullopt;
    const auto& [lo, hi] = *volume_boxes[index];
    return glm::vec3(volumePlacement(v, frame) * glm::vec4(0.5f * (lo + hi), 1.0f));
}

int ViewerState::environmentLight() const {
    const std::vector<Light>& lights = editor.scene().lights;
    if (selected_light >= 0 && selected_light < int(lights.size()) && lights[size_t(selected_light)].environment) return selected_light;
    for (size_t i = 0; i < lights.size(); ++i)
        if (lights[i].environment && lights[i].enabled) return int(i);
    return -1;
}

void ViewerState::readVolumeBoxes() {
    const std::vector<VolumeSpec>& volumes = editor.scene().volumes;
    std::string key = frame ? std::to_string(*frame) : "-";
    for (const VolumeSpec& v : volumes) key += "|" + v.path + "|" + v.density.name;
    if (key == volume_boxes_key) return;
    volume_boxes_key = key;
    volume_boxes.assign(volumes.size(), std::nullopt);
    for (size_t i = 0; i < volumes.size(); ++i) {
        const VolumeSpec& v = volumes[i];
        try {
            const std::string file = frame ? expandFramePattern(v.path, *frame) : v.path;
            for (const GridSummary& g : summarizeFile(file))
                if (g.name == v.density.name && g.active_voxels > 0)
                    volume_boxes[i] = {glm::vec3(g.world_min.x, g.world_min.y, g.world_min.z), glm::vec3(g.world_max.x, g.world_max.y, g.world_max.z)};
        } catch (const std::exception&) {   // the render names the problem
        }
    }
}

void ViewerState::updateBounds() {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    const std::vector<VolumeSpec>& volumes = editor.scene().volumes;
    for (size_t i = 0; i < volumes.size() && i < volume_boxes.size(); ++i) {
        if (!volumes[i].enabled || !volume_boxes[i]) continue;
        const auto& box = *volume_boxes[i];
        for (const glm::mat4& placement : instancePlacements(volumes[i], frame))
            for (int corner = 0; corner < 8; ++corner) {
                const glm::vec3 p(box[corner & 1].x, box[(corner >> 1) & 1].y, box[(corner >> 2) & 1].z);
                const glm::vec3 placed(placement * glm::vec4(p, 1.0f));
                lo = glm::min(lo, placed);
                hi = glm::max(hi, placed);
            }
    }
    if (lo.x <= hi.x) bounds_lo = lo, bounds_hi = hi;
}

Camera ViewerState::camera() const {
    const glm::vec3 pivot = 0.5f * (bounds_lo + bounds_hi);
    if (editor.scene().camera) return lookAtForm(posedCamera(*editor.scene().camera, frame.value_or(0)), pivot);
    if (render)
        if (const auto frame = render->latest()) return lookAtForm(frame->camera, pivot);
    return Camera{};
}

}  // namespace voxlux
