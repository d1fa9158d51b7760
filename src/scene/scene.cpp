// What the scene model answers about itself (scene.h).
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

namespace voxlux {

namespace {

glm::mat4 pose(glm::vec3 translate, glm::vec3 rotate, glm::vec3 scale, RotateOrder order) {
    return glm::translate(glm::mat4(1.0f), translate) * glm::mat4(rotationMatrix(rotate, order)) * glm::scale(glm::mat4(1.0f), scale);
}

}  // namespace

glm::mat3 rotationMatrix(glm::vec3 degrees, RotateOrder order) {
    const glm::vec3 r = glm::radians(degrees);
    const glm::mat3 turn[3] = {glm::mat3(glm::rotate(glm::mat4(1.0f), r.x, glm::vec3(1, 0, 0))),
                               glm::mat3(glm::rotate(glm::mat4(1.0f), r.y, glm::vec3(0, 1, 0))),
                               glm::mat3(glm::rotate(glm::mat4(1.0f), r.z, glm::vec3(0, 0, 1)))};
    const char* axes = kRotateOrderNames[int(order)];   // the first applied is the rightmost factor
    return turn[axes[2] - 'x'] * turn[axes[1] - 'x'] * turn[axes[0] - 'x'];
}

glm::mat4 volumeTransformMatrix(const VolumeTransform& t, std::optional<double> frame) {
    if (t.matrix) return *t.matrix;
    if (t.keys.empty()) return pose(t.translate, t.rotate, t.scale, t.rotate_order);
    const KeyBlend k = keyBlend(t.keys, frame.value_or(t.keys.front().frame));
    const TransformKey& a = t.keys[k.a];
    const TransformKey& b = t.keys[k.b];
    const float w = k.weight;   // 0 where a key is held: the mix is that key exactly
    return pose(glm::mix(a.translate, b.translate, w), glm::mix(a.rotate, b.rotate, w), glm::mix(a.scale, b.scale, w), t.rotate_order);
}

KeyBlend keyBlend(const std::vector<TransformKey>& keys, double frame) {
    if (frame <= keys.front().frame) return {};
    if (frame >= keys.back().frame) return {keys.size() - 1, keys.size() - 1, 0.0f};
    const size_t b = size_t(std::upper_bound(keys.begin(), keys.end(), frame, [](double x, const TransformKey& k) { return x < k.frame; }) -
                            keys.begin());
    return {b - 1, b, float((frame - keys[b - 1].frame) / (keys[b].frame - keys[b - 1].frame))};
}

glm::mat4 volumePlacement(const VolumeSpec& volume, std::optional<double> frame) {
    return volume.transform ? volumeTransformMatrix(*volume.transform, frame) : glm::mat4(1.0f);
}

std::vector<glm::mat4> instancePlacements(const VolumeSpec& volume, std::optional<double> frame) {
    const glm::mat4 placement = volumePlacement(volume, frame);
    if (volume.instances.empty()) return {placement};
    std::vector<glm::mat4> out;
    for (const VolumeTransform& instance : volume.instances) out.push_back(volumeTransformMatrix(instance) * placement);
    return out;
}

size_t placedVolumeCount(const Scene& scene) {
    size_t n = 0;
    for (const VolumeSpec& v : scene.volumes) n += std::max<size_t>(1, v.instances.size());
    return n;
}

namespace {

// Whether `scene` places more than one volume or one that is not visible, its mesh holdouts' cells
// counted when `cells`.
bool placesSeveralOf(const Scene& scene, bool cells) {
    size_t placed = 0;
    bool hidden = false;
    for (const VolumeSpec& v : scene.volumes) {
        if (v.holdout_mesh && !cells) continue;
        placed += std::max<size_t>(1, v.instances.size());
        hidden = hidden || v.role != VolumeRole::Visible;
    }
    return placed > 1 || hidden;
}

}  // namespace

bool placesSeveral(const Scene& scene) { return placesSeveralOf(scene, true); }

bool framesSeveral(const Scene& scene) { return placesSeveralOf(scene, false); }

bool rendersAsSeveral(const Scene& scene) { return placesSeveral(scene) || linksLights(scene); }

bool emits(const Scene& scene) {
    return std::any_of(scene.volumes.begin(), scene.volumes.end(), [](const VolumeSpec& v) {
        return v.enabled && !v.emission.empty() && v.role == VolumeRole::Visible;
    });
}

const VolumeSpec& Scene::volume() const {
    const auto first = std::find_if(volumes.begin(), volumes.end(), [](const VolumeSpec& v) { return v.enabled; });
    return first != volumes.end() ? *first : volumes.front();
}

VolumeSpec& Scene::volume() { return const_cast<VolumeSpec&>(std::as_const(*this).volume()); }

Scene withEnabledVolumes(Scene scene) {
    std::erase_if(scene.volumes, [](const VolumeSpec& v) { return !v.enabled; });
    return scene;
}

Scene renderedScene(Scene scene) {
    scene = withEnabledVolumes(std::move(scene));
    const auto named = [&](const std::string& name) {
        return std::any_of(scene.volumes.begin(), scene.volumes.end(), [&](const VolumeSpec& v) { return v.name == name; });
    };
    for (size_t h = 0; h < scene.holdouts.size(); ++h) {
        if (scene.holdouts[h].mesh.empty()) continue;
        VolumeSpec cells;
        cells.name = "holdout_" + std::to_string(h);
        while (named(cells.name)) cells.name += "_";
        // No path: its mesh is the holdout's (in /holdouts and /input/holdout_files), so that what
        // reads the volumes' paths (the first volume's load) does not follow a mesh.
        cells.role = VolumeRole::ShadowOnly;
        cells.holdout_mesh = h;
        // Opaque and black: a cell the mesh fills has an optical depth of 20 along its edge (a
        // shadow ray keeps e^-20 of its light) and scatters nothing; the mesh's transform is in its
        // voxels, which are made in the world.
        cells.material.density_scale = 20.0f;
        cells.material.albedo = glm::vec3(0.0f);
        cells.material.density_units = DensityUnits::Voxel;
        scene.volumes.push_back(std::move(cells));
    }
    return scene;
}

int enabledLightCount(const Scene& scene, bool ambient) {
    return int(std::count_if(scene.lights.begin(), scene.lights.end(),
                             [&](const Light& l) {
                                 return l.enabled && l.type != LightType::Environment && (l.type == LightType::Ambient) == ambient;
                             }));
}

const std::vector<std::string>& knownAovs() {
    static const std::vector<std::string> aovs{"direct",   "ambient",  "indirect", "emission",    "transmittance",
                                               "depth",    "variance", "coverage", "light_groups"};
    return aovs;
}

LightGroups lightGroups(const Scene& scene) {
    LightGroups groups;
    const bool asked = std::any_of(scene.output.aovs.begin(), scene.output.aovs.end(), [](const AovSpec& a) { return a.name == "light_groups"; });
    if (!asked) return groups;
    for (const Light& l : scene.lights) {
        const std::string name = l.group.empty() ? "default" : l.group;
        const auto at = std::find(groups.names.begin(), groups.names.end(), name);
        groups.of_light.push_back(int(at - groups.names.begin()));
        if (at == groups.names.end()) groups.names.push_back(name);
    }
    if (groups.names.empty()) groups.names.push_back("default");
    return groups;
}

int lightGroupMarches(const Scene& scene) {
    const size_t groups = lightGroups(scene).names.size();
    return groups == 0 ? 1 : int(groups) + (emits(scene) ? 1 : 0);
}

bool linksLights(const Scene& scene) {
    return std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.enabled && (l.volumes || l.shadow_volumes); });
}

LightLinks lightLinks(const Scene& scene) {
    LightLinks links;
    links.of_light.assign(scene.lights.size(), 0);
    if (!linksLights(scene)) return links;
    const auto sorted = [](std::optional<std::vector<std::string>> names) {
        if (names) {
            std::sort(names->begin(), names->end());
            names->erase(std::unique(names->begin(), names->end()), names->end());
        }
        return names;
    };
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const LinkSet set{sorted(scene.lights[i].volumes), sorted(scene.lights[i].shadow_volumes)};
        const auto at = std::find(links.sets.begin(), links.sets.end(), set);
        links.of_light[i] = int(at - links.sets.begin());
        if (at == links.sets.end()) links.sets.push_back(set);
    }
    return links;
}

bool isRegion(const std::array<float, 4>& b) { return b[0] >= 0 && b[1] >= 0 && b[0] < b[2] && b[1] < b[3] && b[2] <= 1 && b[3] <= 1; }

glm::ivec4 regionPixels(const RenderSettings& render, int width, int height) {
    if (!render.region) return {0, 0, width, height};
    const std::array<float, 4>& b = *render.region;
    const int x0 = std::clamp(int(std::floor(b[0] * float(width))), 0, width - 1);
    const int y0 = std::clamp(int(std::floor(b[1] * float(height))), 0, height - 1);
    return {x0, y0, std::clamp(int(std::ceil(b[2] * float(width))), x0 + 1, width), std::clamp(int(std::ceil(b[3] * float(height))), y0 + 1, height)};
}

std::string deepPath(const std::string& output_path) {
    const size_t dot = output_path.size() >= 4 ? output_path.size() - 4 : 0;   // ".exr", in any case (scene_read.cpp checks)
    return output_path.substr(0, dot) + ".deep" + output_path.substr(dot);
}

const std::vector<std::string>& knownCompressions() {
    static const std::vector<std::string> names{"none", "zip", "zips", "piz", "dwaa", "dwab", "rle"};
    return names;
}

}  // namespace voxlux
