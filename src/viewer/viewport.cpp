#include "viewer/viewport.h"

#include <algorithm>
#include <cmath>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/gtc/matrix_transform.hpp>
#include <imgui.h>

#include "scene/camera.h"
#include "scene/transform_edit.h"
#include "viewer/display_texture.h"
#include "viewer/orbit_camera.h"

namespace voxlux {
namespace {

ImVec2 im(glm::vec2 v) { return {v.x, v.y}; }
glm::vec2 gl2(ImVec2 v) { return {v.x, v.y}; }

// Screen rectangle of an image of `size` fitted inside [lo, hi), centred.
void fit(glm::vec2 size, glm::vec2 lo, glm::vec2 hi, glm::vec2& out_lo, glm::vec2& out_hi) {
    const glm::vec2 room = hi - lo;
    const float scale = std::min(room.x / size.x, room.y / size.y);
    const glm::vec2 shown = size * scale;
    out_lo = lo + 0.5f * (room - shown);
    out_hi = out_lo + shown;
}

float radius(const ViewerState& s) { return 0.5f * glm::length(s.bounds_hi - s.bounds_lo); }
glm::vec3 centre(const ViewerState& s) { return 0.5f * (s.bounds_lo + s.bounds_hi); }

constexpr float kDegreesPerPixel = 0.4f;   // a gizmo's turn: 90 degrees over 225 pixels

glm::vec3 rotate(glm::vec3 v, float degrees, glm::vec3 axis) {
    return glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(degrees), axis) * glm::vec4(v, 0.0f));
}

// A pixel's size in world units at `point`'s depth: the view's height there over the image's.
float pixelSizeAt(const Camera& camera, glm::vec3 point, float image_height) {
    const float depth = std::max(glm::dot(point - camera.position, -glm::vec3(cameraToWorld(camera)[2])), 1e-3f);
    return 2.0f * depth * std::tan(glm::radians(camera.fov) * 0.5f) / image_height;
}

// The 12 edges of the box [lo, hi] placed by `placement`, each drawn when both ends are in front
// of the camera; `image_lo` is where the image sits on screen.
void drawBox(const Camera& camera, glm::vec2 image_lo, glm::vec2 size, glm::vec3 lo, glm::vec3 hi, const glm::mat4& placement, ImU32 colour) {
    const glm::vec3 c[2] = {lo, hi};
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 4; ++k) {
            // The edge along axis a: the other two axes take the bits of k.
            const int u = (a + 1) % 3, v = (a + 2) % 3;
            glm::vec3 p;
            p[a] = c[0][a];
            p[u] = c[k & 1][u];
            p[v] = c[(k >> 1) & 1][v];
            glm::vec3 q = p;
            q[a] = c[1][a];
            glm::vec2 sp, sq;
            if (projectToImage(camera, size, glm::vec3(placement * glm::vec4(p, 1.0f)), sp) &&
                projectToImage(camera, size, glm::vec3(placement * glm::vec4(q, 1.0f)), sq))
                ImGui::GetBackgroundDrawList()->AddLine(im(image_lo + sp), im(image_lo + sq), colour, 1.0f);
        }
}

}  // namespace

struct Viewport::Texture {
    DisplayTexture texels;
    const ViewFrame* frame = nullptr;   // what it holds (compared by address: frames are never changed)
    std::string aov;
    std::shared_ptr<const ViewFrame> keep;
};

Viewport::Viewport()
    : current_(std::make_unique<Texture>()), held_(std::make_unique<Texture>()), backdrop_(std::make_unique<Texture>()) {}
Viewport::~Viewport() = default;

void Viewport::upload(const ViewerState& state, Texture& t, const ViewFrame& frame) {
    const std::string& aov = frame.image.pixels.empty() ? "beauty" : state.aov;   // a flipbook image holds the beauty alone
    if (t.frame == &frame && t.aov == aov) return;
    const std::vector<uint8_t>& texels = aov_display_.texels(frame, aov, state.editor.scene().color);
    t.texels.upload(frame.image.width, frame.image.height, texels);
    t.frame = &frame;
    t.aov = aov;
}

void Viewport::draw(ViewerState& state, glm::vec2 lo, glm::vec2 hi) {
    ImDrawList* back = ImGui::GetBackgroundDrawList();
    back->AddRectFilled(im(lo), im(hi), IM_COL32(32, 32, 34, 255));
    const std::shared_ptr<const ViewFrame> frame = state.image();
    const Scene& scene = state.editor.scene();
    fit(glm::vec2(scene.render.width, scene.render.height), lo, hi, image_lo_, image_hi_);
    state.widgets["image"] = glm::vec4(image_lo_, image_hi_);
    if (frame && !frame->display_texels.empty()) {
        current_->keep = frame;
        try {
            upload(state, *current_, *frame);
        } catch (const std::exception& e) {   // a colour AOV under a colour edit OCIO refuses
            state.aov = "beauty";
            state.showError(e.what());
            upload(state, *current_, *frame);
        }
        const float split = state.wipe && state.held ? image_lo_.x + state.wipe_at * (image_hi_.x - image_lo_.x) : image_lo_.x;
        const float u = (split - image_lo_.x) / (image_hi_.x - image_lo_.x);
        if (state.region && state.backdrop) {
            // The region's pixels over the image shown when it was drawn.
            backdrop_->keep = state.backdrop;
            upload(state, *backdrop_, *state.backdrop);
            back->AddImage(backdrop_->texels.imguiId(), im(image_lo_), im(image_hi_));
            const std::array<float, 4>& b = *state.region;
            const glm::vec2 size = image_hi_ - image_lo_;
            const glm::vec2 rlo = image_lo_ + glm::vec2(b[0], b[1]) * size, rhi = image_lo_ + glm::vec2(b[2], b[3]) * size;
            back->AddImage(current_->texels.imguiId(), im(rlo), im(rhi), ImVec2(b[0], b[1]), ImVec2(b[2], b[3]));
            back->AddRect(im(rlo), im(rhi), IM_COL32(255, 200, 60, 230), 0.0f, 0, 1.5f);
        } else {
            back->AddImage(current_->texels.imguiId(), ImVec2(split, image_lo_.y), im(image_hi_), ImVec2(u, 0), ImVec2(1, 1));
        }
        if (state.wipe && state.held && !state.region) {
            held_->keep = state.held;
            upload(state, *held_, *state.held);
            back->AddImage(held_->texels.imguiId(), im(image_lo_), ImVec2(split, image_hi_.y), ImVec2(0, 0), ImVec2(u, 1));
            back->AddLine(ImVec2(split, image_lo_.y), ImVec2(split, image_hi_.y), IM_COL32(255, 200, 60, 255), 2.0f);
        }
        // The probe reads the image under the mouse, at whatever level it is.
        probe_.reset();
        const glm::vec2 m = gl2(ImGui::GetIO().MousePos);
        if (!frame->image.pixels.empty() && m.x >= image_lo_.x && m.y >= image_lo_.y && m.x < image_hi_.x && m.y < image_hi_.y) {
            const glm::vec2 f = (m - image_lo_) / (image_hi_ - image_lo_);
            probe_pixel_ = glm::min(glm::ivec2(f * glm::vec2(frame->image.width, frame->image.height)),
                                    glm::ivec2(frame->image.width - 1, frame->image.height - 1));
            probe_ = frame->image.pixels[size_t(probe_pixel_.y) * frame->image.width + probe_pixel_.x].rgba;
            // Pixel coordinates of the full image, whatever level shows.
            probe_pixel_ = glm::ivec2(f * glm::vec2(scene.render.width, scene.render.height));
        }
    }
    back->PushClipRect(im(lo), im(hi), true);   // nothing drawn over the panels
    if (state.show_guides) guides(state);
    gizmos(state, lo, hi);
    back->PopClipRect();
    mouse(state, lo, hi);
}

void Viewport::guides(const ViewerState& state) {
    ImDrawList* back = ImGui::GetBackgroundDrawList();
    const Camera camera = state.camera();
    const glm::vec2 size = image_hi_ - image_lo_;
    drawBox(camera, image_lo_, size, state.bounds_lo, state.bounds_hi, glm::mat4(1.0f), IM_COL32(150, 150, 160, 160));
    // The axis triad in the lower left corner: the world axes as the camera sees them.
    const glm::mat4 world_to_camera = glm::inverse(cameraToWorld(camera));
    const glm::vec2 origin(image_lo_.x + 36.0f, image_hi_.y - 36.0f);
    const char* names[3] = {"x", "y", "z"};
    const ImU32 colours[3] = {IM_COL32(230, 80, 70, 255), IM_COL32(110, 200, 80, 255), IM_COL32(80, 140, 240, 255)};
    for (int a = 0; a < 3; ++a) {
        glm::vec3 axis(0.0f);
        axis[a] = 1.0f;
        const glm::vec3 seen = glm::vec3(world_to_camera * glm::vec4(axis, 0.0f));
        const glm::vec2 tip = origin + glm::vec2(seen.x, -seen.y) * 24.0f;
        back->AddLine(im(origin), im(tip), colours[a], 2.0f);
        back->AddText(im(tip + glm::vec2(2.0f, -7.0f)), colours[a], names[a]);
    }
}

bool Viewport::dragLight(ViewerState& state, int index, glm::vec2 by, glm::vec2 image_size) {
    const Light& light = state.editor.scene().lights.at(size_t(index));
    if (light.environment) {   // across the screen turns the map about its up: its cut is kept
        Light turned = light;
        turned.environment->rotation = std::remainder(light.environment->rotation + by.x * kDegreesPerPixel, 360.0f);
        return state.editor.setLight(index, turned);
    }
    const Camera camera = state.camera();
    const glm::mat4 frame = cameraToWorld(camera);
    const glm::vec3 right(frame[0]), up(frame[1]);
    Light moved = light;
    if (light.type == LightType::Point || (light.type == LightType::Spot && !ImGui::GetIO().KeyShift)) {
        // Move in the plane facing the camera through the light.
        moved.position += (right * by.x - up * by.y) * pixelSizeAt(camera, light.position, image_size.y);
    } else if (light.type == LightType::Directional || light.type == LightType::Spot) {
        // Turn the direction: across the screen about the camera's up, up and down about its right.
        moved.direction = glm::normalize(rotate(rotate(light.direction, by.x * kDegreesPerPixel, up), by.y * kDegreesPerPixel, right));
    }
    return state.editor.setLight(index, moved);
}

bool Viewport::dragVolume(ViewerState& state, int index, glm::vec2 by, glm::vec2 image_size) {
    const std::vector<VolumeSpec>& volumes = state.editor.scene().volumes;
    if (index < 0 || index >= int(volumes.size())) return false;
    const VolumeTransform t = volumes[size_t(index)].transform.value_or(VolumeTransform{});
    const std::optional<glm::vec3> pivot = state.volumePivot(size_t(index));
    if (!pivot) return false;   // the panel says what places it
    const Camera camera = state.camera();
    const glm::mat4 frame = cameraToWorld(camera);
    const glm::vec3 right(frame[0]), up(frame[1]);
    switch (state.volume_gizmo) {
    case VolumeGizmo::Move:
        return state.editor.setVolumeTransform(index, movedBy(t, (right * by.x - up * by.y) * pixelSizeAt(camera, *pivot, image_size.y)));
    case VolumeGizmo::Rotate: {
        // As a light's direction turns: across the screen about the camera's up, up and down about its right.
        const glm::mat4 turn = glm::rotate(glm::rotate(glm::mat4(1.0f), glm::radians(by.y * kDegreesPerPixel), right),
                                           glm::radians(by.x * kDegreesPerPixel), up);
        return state.editor.setVolumeTransform(index, turnedAbout(t, glm::mat3(turn), *pivot));
    }
    case VolumeGizmo::Scale:   // right or up grows it, 1% a pixel
        return state.editor.setVolumeTransform(index, scaledAbout(t, std::exp((by.x - by.y) * 0.01f), *pivot));
    }
    return false;
}

void Viewport::gizmos(ViewerState& state, glm::vec2 lo, glm::vec2 hi) {
    ImDrawList* fg = ImGui::GetBackgroundDrawList();
    const Camera camera = state.camera();
    const glm::vec2 size = image_hi_ - image_lo_;
    const auto toScreen = [&](glm::vec3 p, glm::vec2& out) {
        if (!projectToImage(camera, size, p, out)) return false;
        out += image_lo_;
        return true;
    };
    const std::vector<Light>& lights = state.editor.scene().lights;
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const bool inside = mouse.x >= lo.x && mouse.y >= lo.y && mouse.x < hi.x && mouse.y < hi.y;
    const bool free = inside && !ImGui::GetIO().WantCaptureMouse && !ImGui::GetIO().KeyAlt;
    for (size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        if (l.type == LightType::Ambient || l.type == LightType::Environment) continue;
        const bool selected = int(i) == state.selected_light;
        const ImU32 colour = !l.enabled ? IM_COL32(120, 120, 120, 200) : selected ? IM_COL32(255, 200, 60, 255) : IM_COL32(230, 230, 230, 220);
        // The handle: the light's position, or for a directional light the point it shines from.
        const glm::vec3 handle = l.type == LightType::Directional ? centre(state) - glm::normalize(l.direction) * 1.3f * radius(state) : l.position;
        glm::vec2 h, tip;
        if (!toScreen(handle, h)) continue;
        const glm::vec3 towards = l.type == LightType::Directional ? centre(state) - glm::normalize(l.direction) * 0.9f * radius(state)
                                                                   : l.position + glm::normalize(l.direction) * 0.4f * radius(state);
        if (l.type != LightType::Point && toScreen(towards, tip)) {
            fg->AddLine(im(h), im(tip), colour, 2.0f);
            const glm::vec2 d = glm::normalize(tip - h + glm::vec2(1e-6f)), n(-d.y, d.x);
            fg->AddTriangleFilled(im(tip), im(tip - d * 10.0f + n * 5.0f), im(tip - d * 10.0f - n * 5.0f), colour);
        }
        if (l.type == LightType::Spot) {   // the cone: its rim at 0.4 radii along the direction
            const glm::vec3 dir = glm::normalize(l.direction);
            const glm::vec3 a = glm::normalize(glm::cross(dir, std::abs(dir.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0)));
            const glm::vec3 b = glm::cross(dir, a);
            const float reach = 0.4f * radius(state), rim = reach * std::tan(glm::radians(l.cone_angle));
            const float inner = reach * std::tan(glm::radians(std::max(l.cone_angle - l.cone_softness, 0.0f)));
            for (float r : {rim, inner}) {
                glm::vec2 prev{};
                for (int k = 0; k <= 24; ++k) {
                    const float t = float(k) / 24.0f * 6.2831853f;
                    glm::vec2 p;
                    if (!toScreen(l.position + dir * reach + (a * std::cos(t) + b * std::sin(t)) * r, p)) break;
                    if (k > 0) fg->AddLine(im(prev), im(p), colour, r == rim ? 1.5f : 1.0f);
                    if (k % 6 == 0 && r == rim) fg->AddLine(im(h), im(p), colour, 1.0f);
                    prev = p;
                }
            }
        }
        const bool over = glm::length(gl2(mouse) - h) < 9.0f;
        fg->AddCircleFilled(im(h), 7.0f, colour);
        state.widgets["light/" + std::to_string(i) + "/handle"] = glm::vec4(h - glm::vec2(7.0f), h + glm::vec2(7.0f));
        if (over || dragging_light_ == int(i)) fg->AddCircle(im(h), 10.0f, IM_COL32(255, 255, 255, 255), 0, 2.0f);
        if (over && free && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
            dragging_light_ = int(i);
            state.selected_light = int(i);
        }
    }
    if (dragging_light_ >= 0) {
        if (!ImGui::IsMouseDown(ImGuiMouseButton_Left) || dragging_light_ >= int(lights.size())) {
            dragging_light_ = -1;
        } else {
            const ImVec2 d = ImGui::GetIO().MouseDelta;
            if (d.x != 0.0f || d.y != 0.0f) dragLight(state, dragging_light_, gl2(d), size);
        }
    }
    // Each enabled volume's handle at its box's centre, named with the gizmo's mode under the
    // mouse; the selected volume's box drawn as placed.
    const std::vector<VolumeSpec>& volumes = state.editor.scene().volumes;
    for (size_t i = 0; i < volumes.size(); ++i) {
        const std::optional<glm::vec3> pivot = state.volumePivot(i);
        glm::vec2 h;
        if (!volumes[i].enabled || !pivot || !toScreen(*pivot, h)) continue;
        const bool selected = int(i) == state.selected_volume;
        const ImU32 colour = selected ? IM_COL32(255, 200, 60, 255) : IM_COL32(90, 200, 230, 220);
        if (selected) {
            const auto& [box_lo, box_hi] = *state.volume_boxes[i];
            drawBox(camera, image_lo_, size, box_lo, box_hi, volumePlacement(volumes[i], state.frame), colour);
        }
        const bool over = glm::length(gl2(mouse) - h) < 9.0f;
        fg->AddRectFilled(im(h - glm::vec2(6.0f)), im(h + glm::vec2(6.0f)), colour);
        if (over || dragging_volume_ == int(i)) {
            fg->AddRect(im(h - glm::vec2(9.0f)), im(h + glm::vec2(9.0f)), IM_COL32(255, 255, 255, 255), 0.0f, 0, 2.0f);
            fg->AddText(im(h + glm::vec2(12.0f, -7.0f)), colour, (volumes[i].name + ": " + kVolumeGizmoNames[size_t(state.volume_gizmo)]).c_str());
        }
        state.widgets["volume/" + std::to_string(i) + "/handle"] = glm::vec4(h - glm::vec2(6.0f), h + glm::vec2(6.0f));
        if (over && free && dragging_light_ < 0 && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
            dragging_volume_ = int(i);
            state.selected_volume = int(i);
        }
    }
    if (dragging_volume_ >= 0) {
        if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
            dragging_volume_ = -1;
        } else {
            const ImVec2 d = ImGui::GetIO().MouseDelta;
            if (d.x != 0.0f || d.y != 0.0f) dragVolume(state, dragging_volume_, gl2(d), size);
        }
    }
}

// Ctrl + left drag draws the render region over the image; Ctrl + click clears it.
void Viewport::region(ViewerState& state) {
    const ImGuiIO& io = ImGui::GetIO();
    const glm::vec2 m = gl2(io.MousePos);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left) && io.KeyCtrl && navigating_[ImGuiMouseButton_Left]) region_from_ = m;
    if (!region_from_) return;
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
        ImGui::GetBackgroundDrawList()->AddRect(im(glm::min(*region_from_, m)), im(glm::max(*region_from_, m)), IM_COL32(255, 200, 60, 255));
        return;
    }
    const glm::vec2 size = image_hi_ - image_lo_;
    const glm::vec2 a = glm::clamp((glm::min(*region_from_, m) - image_lo_) / size, 0.0f, 1.0f);
    const glm::vec2 b = glm::clamp((glm::max(*region_from_, m) - image_lo_) / size, 0.0f, 1.0f);
    region_from_.reset();
    if (glm::any(glm::lessThan((b - a) * size, glm::vec2(4.0f)))) {   // a click, or a box off the image
        state.region.reset();
        return;
    }
    if (!state.region) state.backdrop = state.image();
    state.region = std::array<float, 4>{a.x, a.y, b.x, b.y};
}

void Viewport::mouse(ViewerState& state, glm::vec2 lo, glm::vec2 hi) {
    ImGuiIO& io = ImGui::GetIO();
    // A drag moves the camera when it began in the viewport (not on a panel, not on a light).
    for (int b = 0; b < 3; ++b)
        if (ImGui::IsMouseClicked(b)) {
            const glm::vec2 m = gl2(io.MousePos);
            navigating_[b] = !io.WantCaptureMouse && dragging_light_ < 0 && dragging_volume_ < 0 && m.x >= lo.x && m.y >= lo.y && m.x < hi.x && m.y < hi.y;
        }
    if (!io.WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed(GLFW_KEY_F, false)) {
            state.updateBounds();   // the volumes as they are placed now
            state.editor.setCamera(frameAlong(state.camera(), state.bounds_lo, state.bounds_hi));
        }
        const int gizmo_keys[3] = {GLFW_KEY_W, GLFW_KEY_E, GLFW_KEY_R};
        for (int m = 0; m < 3; ++m)
            if (ImGui::IsKeyPressed(gizmo_keys[m], false)) state.volume_gizmo = VolumeGizmo(m);
    }
    if (io.WantCaptureMouse || dragging_light_ >= 0 || dragging_volume_ >= 0) return;
    const glm::vec2 d = gl2(io.MouseDelta);
    const float height = std::max(image_hi_.y - image_lo_.y, 1.0f);
    std::optional<Camera> moved;
    const Camera camera = state.camera();
    const auto dragging = [&](ImGuiMouseButton b) { return navigating_[b] && ImGui::IsMouseDown(b) && (d.x != 0 || d.y != 0); };
    if (dragging(ImGuiMouseButton_Left) && !io.KeyCtrl) moved = orbit(camera, -d.x * 0.3f, d.y * 0.3f);
    region(state);
    if (dragging(ImGuiMouseButton_Middle)) moved = pan(camera, glm::vec2(-d.x, d.y) / height);
    if (dragging(ImGuiMouseButton_Right) && io.KeyShift) {
        if (const int environment = state.environmentLight(); environment >= 0) dragLight(state, environment, d, image_hi_ - image_lo_);
    } else if (dragging(ImGuiMouseButton_Right)) {
        moved = dolly(camera, std::exp(-(d.x - d.y) * 0.005f));
    }
    const glm::vec2 m = gl2(io.MousePos);
    if (io.MouseWheel != 0.0f && m.x >= lo.x && m.y >= lo.y && m.x < hi.x && m.y < hi.y) moved = dolly(camera, std::pow(0.9f, io.MouseWheel));
    if (moved) state.editor.setCamera(*moved);
}

}  // namespace voxlux
