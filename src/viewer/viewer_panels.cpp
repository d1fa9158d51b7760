#include "viewer/viewer_panels.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <cstdio>
#include <filesystem>

#include <imgui.h>
#include <imgui_stdlib.h>
#include <glm/gtx/component_wise.hpp>

#include "core/frame_pattern.h"
#include "grade/color_pipeline.h"
#include "scene/quality_presets.h"
#include "scene/scene_json.h"
#include "volume/vdb_file.h"

namespace voxlux {
namespace {

using Pointer = nlohmann::json::json_pointer;

constexpr float kStopsPerPixel = 0.01f;   // exposure drags: 60 pixels are 0.6 stops

void remember(ViewerState& state, const std::string& name) {
    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    state.widgets[name] = glm::vec4(lo.x, lo.y, hi.x, hi.y);
}

bool setKey(ViewerState& state, const std::string& pointer, const nlohmann::json& value) {
    return state.editor.edit(pointer, [&](nlohmann::json& j) { j[Pointer(pointer)] = value; });
}

// A combo over `items`; returns the pick when it changed.
std::optional<std::string> combo(const char* label, const std::string& current, const std::vector<std::string>& items) {
    std::optional<std::string> picked;
    if (ImGui::BeginCombo(label, current.empty() ? "(default)" : current.c_str())) {
        for (const auto& item : items)
            if (ImGui::Selectable(item.c_str(), item == current) && item != current) picked = item;
        ImGui::EndCombo();
    }
    return picked;
}

// Any JSON value as widgets: objects and arrays as tree nodes, numbers as drags, and so on.
// Every change is one edit of the key at `pointer`.
void jsonWidget(ViewerState& state, const std::string& label, const nlohmann::json& value, const std::string& pointer) {
    ImGui::PushID(pointer.c_str());
    const bool numbers = value.is_array() && !value.empty() && value.size() <= 4 &&
                         std::all_of(value.begin(), value.end(), [](const nlohmann::json& v) { return v.is_number(); });
    if (numbers) {
        float v[4];
        for (size_t i = 0; i < value.size(); ++i) v[i] = value[i].get<float>();
        if (ImGui::DragScalarN(label.c_str(), ImGuiDataType_Float, v, int(value.size()), 0.01f)) {
            nlohmann::json out = nlohmann::json::array();
            for (size_t i = 0; i < value.size(); ++i) out.push_back(value[i].is_number_integer() ? nlohmann::json(std::lround(v[i])) : nlohmann::json(v[i]));
            setKey(state, pointer, out);
        }
    } else if (value.is_object() || value.is_array()) {
        if (ImGui::TreeNode(label.c_str())) {
            if (value.is_object())
                for (const auto& [key, child] : value.items()) jsonWidget(state, key, child, pointer + "/" + key);
            else
                for (size_t i = 0; i < value.size(); ++i) jsonWidget(state, std::to_string(i), value[i], pointer + "/" + std::to_string(i));
            ImGui::TreePop();
        }
    } else if (value.is_boolean()) {
        bool v = value.get<bool>();
        if (ImGui::Checkbox(label.c_str(), &v)) setKey(state, pointer, v);
    } else if (value.is_number_integer()) {
        int v = value.get<int>();
        if (ImGui::DragInt(label.c_str(), &v, 0.2f)) setKey(state, pointer, v);
    } else if (value.is_number()) {
        float v = value.get<float>();
        if (ImGui::DragFloat(label.c_str(), &v, std::max(std::abs(v) * 0.01f, 0.001f), 0.0f, 0.0f, "%.4g")) setKey(state, pointer, v);
    } else if (value.is_string()) {
        std::string v = value.get<std::string>();
        if (ImGui::InputText(label.c_str(), &v, ImGuiInputTextFlags_EnterReturnsTrue)) setKey(state, pointer, v);
    } else {
        ImGui::TextDisabled("%s: (unset)", label.c_str());
    }
    ImGui::PopID();
}

void lightList(ViewerState& state) {
    const std::vector<Light> lights = state.editor.scene().lights;   // a copy: an edit replaces the scene
    for (size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        ImGui::PushID(int(i));
        bool on = l.enabled;
        if (ImGui::Checkbox("##on", &on)) state.editor.enableLight(int(i), on);
        remember(state, "light/" + std::to_string(i) + "/enable");
        ImGui::SameLine();
        // The light's name, its light group (output.aovs "light_groups") and the volumes it is linked to.
        std::string name = (l.name.empty() ? "light " + std::to_string(i) : l.name) + "  [" + (l.group.empty() ? "default" : l.group) + "]";
        if (l.volumes) {
            std::string linked;
            for (const std::string& v : *l.volumes) linked += (linked.empty() ? "" : ", ") + v;
            name += "  -> " + (linked.empty() ? std::string("no volume") : linked);
        }
        if (ImGui::Selectable(name.c_str(), state.selected_light == int(i), 0, ImVec2(190, 0))) state.selected_light = int(i);
        ImGui::SameLine();
        if (ImGui::SmallButton(state.editor.soloedLight(int(i)) ? "unsolo" : "solo")) state.editor.soloLight(int(i));
        ImGui::SameLine();
        if (ImGui::SmallButton("remove")) state.editor.removeLight(int(i));
        ImGui::PopID();
    }
    for (const char* type : {"directional", "point", "spot", "ambient"}) {
        if (ImGui::SmallButton((std::string("+ ") + type).c_str())) {
            nlohmann::json light = {{"type", type}, {"intensity", 1.0}, {"name", std::string(type) + " " + std::to_string(lights.size())}};
            const glm::vec3 c = 0.5f * (state.bounds_lo + state.bounds_hi);
            const float r = 0.5f * glm::length(state.bounds_hi - state.bounds_lo);
            if (std::string(type) == "point" || std::string(type) == "spot") light["position"] = {c.x, c.y + 1.5f * r, c.z};
            if (std::string(type) == "spot" || std::string(type) == "directional") light["direction"] = {0, -1, 0};
            if (state.editor.addLight(light)) state.selected_light = int(lights.size());
        }
        ImGui::SameLine();
    }
    ImGui::NewLine();
}

// Light linking: a checkbox per volume for the volumes the light lights and those that shadow it;
// every box ticked is no list (every volume, also those added later).
void linkEditor(ViewerState& state, int i, const Light& l) {
    const std::vector<VolumeSpec>& volumes = state.editor.scene().volumes;
    for (const auto& [key, list] : {std::pair{"volumes", l.volumes}, std::pair{"shadow_volumes", l.shadow_volumes}}) {
        ImGui::TextUnformatted(std::string(key) == "volumes" ? "lights" : "shadowed by");
        for (const VolumeSpec& v : volumes) {
            bool in = !list || std::find(list->begin(), list->end(), v.name) != list->end();
            ImGui::SameLine();
            if (!ImGui::Checkbox((v.name + "##" + key).c_str(), &in)) continue;
            nlohmann::json names = nlohmann::json::array();
            for (const VolumeSpec& other : volumes)
                if (other.name == v.name ? in : !list || std::find(list->begin(), list->end(), other.name) != list->end()) names.push_back(other.name);
            state.editor.changeLight(i, {{key, names.size() == volumes.size() ? nlohmann::json(nullptr) : names}});
        }
    }
}

// The .exr files beside `map`, for the map chooser: the folder an artist keeps a set's HDRIs in.
const std::vector<std::string>& mapsBeside(const std::string& map) {
    static std::map<std::string, std::vector<std::string>> listed;   // by folder, read once
    const std::filesystem::path folder = std::filesystem::path(map).parent_path();
    const auto [at, added] = listed.try_emplace(folder.string());
    if (added) {
        std::error_code error;
        for (const auto& entry : std::filesystem::directory_iterator(folder.empty() ? "." : folder, error))
            if (entry.path().extension() == ".exr") at->second.push_back((folder / entry.path().filename()).string());
        std::sort(at->second.begin(), at->second.end());
    }
    return at->second;
}

// An environment light's map: picked beside the current one or typed (Enter), and its thumbnail.
void environmentMapControls(ViewerState& state, EnvironmentThumbnailWidget& thumbnail, int i) {
    const std::string& map = state.editor.scene().lights[size_t(i)].environment->map;
    if (auto picked = combo("map", map, mapsBeside(map))) state.editor.changeLight(i, {{"map", *picked}});
    static std::string typed;
    if (ImGui::InputTextWithHint("##map path", "another map: path, Enter", &typed, ImGuiInputTextFlags_EnterReturnsTrue) &&
        state.editor.changeLight(i, {{"map", typed}}))
        typed.clear();
    remember(state, "light/map");
    thumbnail.draw(state.editor.scene(), size_t(i));
}

void lightEditor(ViewerState& state, EnvironmentThumbnailWidget& thumbnail) {
    const std::vector<Light>& lights = state.editor.scene().lights;
    if (state.selected_light < 0 || state.selected_light >= int(lights.size())) return;
    const int i = state.selected_light;
    Light l = lights[size_t(i)];
    ImGui::Separator();
    std::string name = l.name;
    if (ImGui::InputText("name", &name, ImGuiInputTextFlags_EnterReturnsTrue)) state.editor.renameLight(i, name);
    // Its light group; solo shows the group's lights alone, as its layer of the light_groups AOV.
    std::string group = l.group;
    if (ImGui::InputText("group", &group, ImGuiInputTextFlags_EnterReturnsTrue))   // empty: back to the default group
        state.editor.changeLight(i, {{"group", group.empty() ? nlohmann::json(nullptr) : nlohmann::json(group)}});
    ImGui::SameLine();
    if (ImGui::SmallButton(state.editor.soloedGroup(l.group) ? "unsolo group" : "solo group")) state.editor.soloGroup(l.group);
    if (l.type != LightType::Ambient && l.type != LightType::Environment) linkEditor(state, i, l);
    const std::string type = l.type == LightType::Point ? "point" : l.type == LightType::Spot ? "spot" : l.type == LightType::Ambient ? "ambient" : "directional";
    if (l.type == LightType::Environment)   // a map is not a setting of the other types: no switching
        environmentMapControls(state, thumbnail, i);
    else if (auto t = combo("type", type, {"directional", "point", "spot", "ambient"}))
        state.editor.changeLight(i, {{"type", *t}});
    bool changed = ImGui::ColorEdit3("colour", &l.color.x, ImGuiColorEditFlags_Float);
    // Intensity as exposure: a stop doubles it, as a lighter expects. Dragged a hundredth of a stop
    // a pixel (Dear ImGui's Shift: ten times that, Alt: a hundredth of it), so a small move is a small change.
    float stops = std::log2(std::max(l.intensity, 1e-6f));
    if (ImGui::DragFloat("exposure (stops)", &stops, kStopsPerPixel, -20.0f, 20.0f, "%.2f")) {
        l.intensity = std::exp2(stops);
        changed = true;
    }
    remember(state, "light/exposure");
    if (l.type == LightType::Point || l.type == LightType::Spot) changed |= ImGui::DragFloat3("position", &l.position.x, 0.01f);
    if (l.type == LightType::Directional || l.type == LightType::Spot) {
        if (ImGui::DragFloat3("direction", &l.direction.x, 0.01f) && glm::length(l.direction) > 1e-6f) changed = true;
    }
    if (auto& e = l.environment) {
        // A turn of the map moves its median-cut lights only: the cut is kept (docs/environment.md).
        changed |= ImGui::DragFloat("rotation", &e->rotation, 0.5f, -360.0f, 360.0f, "%.1f deg");
        remember(state, "light/rotation");
        changed |= ImGui::Checkbox("visible to camera", &e->visible_to_camera);
        changed |= ImGui::SliderInt("median-cut lights", &e->median_cut_lights, 0, 64);
    }
    if (l.type == LightType::Spot) {
        changed |= ImGui::SliderFloat("cone angle", &l.cone_angle, 1.0f, 89.0f, "%.1f deg");
        changed |= ImGui::SliderFloat("cone softness", &l.cone_softness, 0.0f, l.cone_angle, "%.1f deg");
    }
    if (changed) state.editor.setLight(i, l);
}

// The float grids of `volume`'s file at the frame shown, each file read once.
const std::vector<std::string>& densityGrids(const ViewerState& state, const VolumeSpec& volume) {
    static std::map<std::string, std::vector<std::string>> grids;
    const std::string file = state.frame ? expandFramePattern(volume.path, *state.frame) : volume.path;
    const auto [at, added] = grids.try_emplace(file);
    if (added) {
        try {
            const VdbFile vdb(file);
            for (const auto& g : vdb.grids())
                if (g.value_type == "float" || g.value_type == "half") at->second.push_back(g.name);
        } catch (const std::exception&) {   // the render names the problem; the list stays empty
        }
    }
    return at->second;
}

void colourControls(ViewerState& state) {
    const ColorSettings& c = state.editor.scene().color;
    static std::string config_key;
    static std::vector<std::string> displays;
    static std::map<std::string, std::vector<std::string>> views;
    if (config_key != c.config + "|") {
        config_key = c.config + "|";
        displays.clear();
        views.clear();
        try {
            std::string source;
            const auto config = loadColorConfig(c, source);
            for (int d = 0; d < config->getNumDisplays(); ++d) {
                displays.push_back(config->getDisplay(d));
                for (int v = 0; v < config->getNumViews(displays.back().c_str()); ++v)
                    views[displays.back()].push_back(config->getView(displays.back().c_str(), v));
            }
        } catch (const std::exception&) {
        }
    }
    if (auto d = combo("display", c.display, displays)) setKey(state, "/color/display", *d);
    const std::string display = c.display.empty() && !displays.empty() ? displays.front() : c.display;
    if (auto v = combo("view", c.view, views[display])) setKey(state, "/color/view", *v);
    float exposure = state.editor.scene().render.exposure;
    if (ImGui::DragFloat("exposure", &exposure, kStopsPerPixel, -20.0f, 20.0f, "%.2f stops")) setKey(state, "/render/exposure", exposure);
}

// Each volume by name: shown or not, its role, and its placement: translate, rotate and scale
// dragged here or with the viewport's gizmo (a move re-runs the framing, lighting and march, not
// the load: docs/scene.md), or what places it when that is a matrix or keys.
void volumeList(ViewerState& state) {
    const std::vector<VolumeSpec> volumes = state.editor.scene().volumes;   // a copy: an edit replaces the scene
    const float extent = std::max(glm::length(state.bounds_hi - state.bounds_lo), 1e-3f);
    ImGui::TextUnformatted("gizmo (W E R):");
    for (size_t m = 0; m < kVolumeGizmoNames.size(); ++m) {
        ImGui::SameLine();
        if (ImGui::RadioButton(kVolumeGizmoNames[m].c_str(), state.volume_gizmo == VolumeGizmo(m))) state.volume_gizmo = VolumeGizmo(m);
    }
    for (size_t i = 0; i < volumes.size(); ++i) {
        const VolumeSpec& v = volumes[i];
        ImGui::PushID(int(i));
        bool on = v.enabled;
        if (ImGui::Checkbox("##on", &on)) state.editor.enableVolume(int(i), on);
        remember(state, "volume/" + std::to_string(i) + "/enable");
        ImGui::SameLine();
        const std::string label = v.name + "  " + std::filesystem::path(v.path).filename().string();
        if (ImGui::Selectable(label.c_str(), state.selected_volume == int(i))) state.selected_volume = state.selected_volume == int(i) ? -1 : int(i);
        if (auto g = combo("density grid", v.density.name, densityGrids(state, v))) setKey(state, "/volumes/" + std::to_string(i) + "/density", *g);
        if (auto role = combo("role", kVolumeRoleNames[size_t(v.role)], kVolumeRoleNames))
            setKey(state, "/volumes/" + std::to_string(i) + "/role", *role);
        const VolumeTransform t = v.transform.value_or(VolumeTransform{});
        if (t.matrix) {
            ImGui::TextDisabled("placed by a matrix (Every key)");
        } else if (!t.keys.empty()) {
            ImGui::TextDisabled("%s", (std::to_string(t.keys.size()) + " keys" + (t.chan.empty() ? "" : " from " + t.chan)).c_str());
        } else {
            VolumeTransform edited = t;
            bool changed = ImGui::DragFloat3("translate", &edited.translate.x, 0.005f * extent);
            changed |= ImGui::DragFloat3("rotate", &edited.rotate.x, 0.5f, 0.0f, 0.0f, "%.1f deg");
            remember(state, "volume/" + std::to_string(i) + "/rotate");
            changed |= ImGui::DragFloat3("scale", &edited.scale.x, 0.005f, 1e-3f, 1e3f);
            int order = int(t.rotate_order);
            changed |= ImGui::Combo("rotate order", &order, kRotateOrderNames, IM_ARRAYSIZE(kRotateOrderNames));
            edited.rotate_order = RotateOrder(order);
            if (changed && glm::compMin(edited.scale) > 0.0f) state.editor.setVolumeTransform(int(i), edited);
        }
        ImGui::PopID();
    }
}

}  // namespace

PanelRequests drawScenePanel(ViewerState& state, EnvironmentThumbnailWidget& thumbnail, float x, float width, float height) {
    PanelRequests out;
    ImGui::SetNextWindowPos(ImVec2(x, 0));
    ImGui::SetNextWindowSize(ImVec2(width, height));
    ImGui::Begin("scene", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::InputText("##save", &state.save_path);
    ImGui::SameLine();
    out.save = ImGui::Button("Save scene");
    remember(state, "save");
    out.render = ImGui::Button("Render");
    ImGui::SameLine();
    // The output path, typed here; it becomes output.path when the field loses the keyboard or
    // Enter is pressed, and follows the scene (an undo) while it is not being typed in.
    if (!state.output_typing) state.output_path = state.editor.scene().output.path;
    ImGui::SetNextItemWidth(-1);
    ImGui::InputTextWithHint("##output", "output .exr (#### for frames)", &state.output_path);
    state.output_typing = ImGui::IsItemActive();
    if (ImGui::IsItemDeactivatedAfterEdit() && state.output_path != state.editor.scene().output.path)
        setKey(state, "/output/path", state.output_path);
    remember(state, "output");

    if (ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen)) {
        lightList(state);
        lightEditor(state, thumbnail);
    }
    if (ImGui::CollapsingHeader("Method and quality", ImGuiTreeNodeFlags_DefaultOpen)) {
        static std::string preset;
        if (auto q = combo("quality", preset, qualityPresetNames()))
            if (state.editor.edit("quality " + *q, [&](nlohmann::json& j) { applyQualityPreset(j, *q); })) preset = *q;
        const nlohmann::json& j = state.editor.json();
        if (auto m = combo("method", j["render"].value("method", "march"), {"march", "reference"})) setKey(state, "/render/method", *m);
        if (auto sh = combo("shadows", j["effects"].value("shadows", "none"), kShadowMethodNames))
            setKey(state, "/effects/shadows", *sh);
        if (auto f = combo("filter", j["render"].value("filter", "trilinear"), {"trilinear", "tricubic"})) setKey(state, "/render/filter", *f);
    }
    if (ImGui::CollapsingHeader("Colour", ImGuiTreeNodeFlags_DefaultOpen)) colourControls(state);
    if (ImGui::CollapsingHeader("Volumes", ImGuiTreeNodeFlags_DefaultOpen)) volumeList(state);
    if (ImGui::CollapsingHeader("Every key")) {
        const nlohmann::json json = state.editor.json();   // a copy: edits replace it
        for (const auto& [key, value] : json.items()) jsonWidget(state, key, value, "/" + key);
    }
    ImGui::End();
    return out;
}

void drawImagePanel(ViewerState& state, const Viewport& viewport, float x, float width, float height) {
    ImGui::SetNextWindowPos(ImVec2(x, 0));
    ImGui::SetNextWindowSize(ImVec2(width, height));
    ImGui::Begin("image", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    if (auto a = combo("AOV", state.aov, kViewAovs)) state.aov = *a;
    const std::shared_ptr<const ViewFrame> frame = state.render->latest();
    if (ImGui::Button("Hold as before") && frame) state.held = frame;
    ImGui::SameLine();
    ImGui::Checkbox("wipe", &state.wipe);
    if (state.wipe) ImGui::SliderFloat("wipe at", &state.wipe_at, 0.0f, 1.0f);
    ImGui::Checkbox("bounding box and axes", &state.show_guides);
    if (state.region) {
        ImGui::SameLine();
        if (ImGui::SmallButton("clear region")) state.region.reset();
    } else {
        ImGui::TextDisabled("Ctrl + drag: render region");
    }
    if (const auto& p = viewport.probe())
        ImGui::Text("pixel %d %d\nRGBA %.4g %.4g %.4g %.4g", viewport.probePixel().x, viewport.probePixel().y, p->x, p->y, p->z, p->w);
    else
        ImGui::TextDisabled("pixel probe: hover the image");
    ImGui::Separator();
    if (frame) {
        ImGui::Text("edit %llu: level %d of %d (%dx%d)%s", (unsigned long long)frame->edit, frame->level + 1, frame->levels,
                    frame->image.width, frame->image.height, frame->converged ? ", converged" : "");
        if (frame->samples > 0)
            ImGui::Text("%d of %d samples a pixel", frame->samples, state.editor.scene().render.reference.spp);
        ImGui::Text("%.0f ms since the edit", frame->seconds_to_image * 1000.0);
        ImGui::TextUnformatted("the edit re-ran:");
        for (const StageReport& s : frame->edit_stages)
            if (s.cached) ImGui::BulletText("%-18s from the frame cache", s.name.c_str());
            else ImGui::BulletText("%-18s %7.1f ms", s.name.c_str(), s.seconds * 1000.0);
        if (const auto& u = frame->light_update) {
            const char* mode = u->mode == LightUpdate::Mode::Selective ? "selective" : u->mode == LightUpdate::Mode::Entire ? "entire" : "kept";
            ImGui::Text("light update: %s, -%d +%d of %d lights", mode, u->lights_out, u->lights_in, u->lights);
        }
        if (state.frame)
            ImGui::Text("frame cache: %zu grids and brick sets, %.0f of %.0f MB", frame->cache_outputs,
                        frame->cache_bytes / 1048576.0, state.frame_cache_bytes / 1048576.0);
        for (const auto& w : frame->warnings) ImGui::TextWrapped("warning: %s", w.c_str());
    } else {
        ImGui::TextUnformatted("rendering the first image...");
    }
    const ViewStatistics st = state.render->statistics();
    ImGui::Separator();
    ImGui::Text("UI %.0f fps", state.ui_fps);
    ImGui::Text("edits %llu, cancelled marches %llu", (unsigned long long)st.submitted, (unsigned long long)st.cancelled);
    ImGui::Text("light updates: %llu selective, %llu entire", (unsigned long long)st.selective_updates, (unsigned long long)st.entire_updates);
    ImGui::End();
}

void drawTimeline(ViewerState& state, float x, float y, float width) {
    if (!state.frame) return;
    ImGui::SetNextWindowPos(ImVec2(x, y));
    ImGui::SetNextWindowSize(ImVec2(width, 0));
    ImGui::Begin("timeline", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoTitleBar);
    ImGui::Checkbox("play", &state.playing);
    ImGui::SameLine();
    // A frame typed (Enter shows it), the slider, and the range with what the flipbook holds.
    int typed = *state.frame;
    ImGui::SetNextItemWidth(70.0f);
    if (ImGui::InputInt("##typed", &typed, 0, 0, ImGuiInputTextFlags_EnterReturnsTrue)) state.showFrame(typed);
    remember(state, "timeline/typed");
    ImGui::SameLine();
    char range[96];
    std::snprintf(range, sizeof range, "%d-%d  %zu cached  %g fps", state.first_frame, state.last_frame, state.flipbook.size(),
                  state.fps());
    int f = *state.frame;
    ImGui::SetNextItemWidth(-ImGui::CalcTextSize(range).x - 2.0f * ImGui::GetStyle().ItemSpacing.x);
    if (ImGui::SliderInt("##frame", &f, state.first_frame, state.last_frame, "frame %d")) state.showFrame(f);
    remember(state, "timeline/frame");
    // A tick under the slider for each frame in the flipbook.
    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    const float span = float(std::max(1, state.last_frame - state.first_frame));
    for (const auto& [kept, image] : state.flipbook) {
        const float x = lo.x + 6.0f + (hi.x - lo.x - 12.0f) * float(kept - state.first_frame) / span;
        ImGui::GetWindowDrawList()->AddLine(ImVec2(x, hi.y - 3.0f), ImVec2(x, hi.y), IM_COL32(110, 200, 120, 255), 2.0f);
    }
    ImGui::SameLine();
    ImGui::TextUnformatted(range);
    ImGui::End();
}

}  // namespace voxlux
