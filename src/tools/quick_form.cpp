#include "tools/quick_form.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>

#include "core/frame_pattern.h"
#include "core/quantile.h"
#include "optics/emission.h"
#include "scene/camera.h"
#include "volume/vdb_loader.h"
#include "volume/volume_stages.h"

namespace voxlux {
namespace {

// Sums f(value) over the active values of `grid` down each column along index axis `axis`
// (tiles count for every voxel they cover); returns the columns' sums that are above zero.
template <class F>
std::vector<double> columnSums(const openvdb::FloatGrid& grid, int axis, F f) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    std::unordered_map<uint64_t, double> columns;
    const auto key = [](int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); };
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        const double value = f(*it);
        if (!(value > 0.0)) continue;
        if (it.isVoxelValue()) {
            columns[key(it.getCoord()[u], it.getCoord()[v])] += value;
            continue;
        }
        const openvdb::CoordBBox box = it.getBoundingBox();
        const double depth = double(box.dim()[axis]);
        for (int a = box.min()[u]; a <= box.max()[u]; ++a)
            for (int b = box.min()[v]; b <= box.max()[v]; ++b) columns[key(a, b)] += value * depth;
    }
    std::vector<double> sums;
    sums.reserve(columns.size());
    for (const auto& [k, s] : columns) sums.push_back(s);
    return sums;
}

// The index axis closest to the world direction the default camera looks from, and whether the
// camera lies toward its larger indices.
struct ViewAxis {
    int axis = 2;
    bool camera_at_max = true;
};
ViewAxis viewAxis(const glm::mat4& index_to_world, const glm::mat3& view_frame) {
    const glm::vec3 back = view_frame[2];
    ViewAxis best;
    float best_cos = -1.0f;
    for (int a = 0; a < 3; ++a) {
        const float c = glm::dot(glm::normalize(glm::vec3(index_to_world[a])), back);
        if (std::abs(c) > best_cos) best_cos = std::abs(c), best = {a, c > 0.0f};
    }
    return best;
}

// The emitted radiance that reaches the camera down each column of `emission` along the view axis:
// each voxel's radiance x its length, dimmed by the optical depth of the density in front of it
// (the voxel's own depth integrated as the march does, (1 - e^-tau) / tau). `radiance` maps an
// emission value to radiance per world unit, `depth_per_density` a density value to the optical
// depth of one voxel along the axis. The two grids share their voxels (Mantaflow's do). Returns the
// columns' sums above zero.
template <class F>
std::vector<double> transmittedColumnEmission(const openvdb::FloatGrid& density, const openvdb::FloatGrid& emission,
                                              ViewAxis view, double depth_per_density, double voxel_length, F radiance) {
    const int a = view.axis, u = (a + 1) % 3, v = (a + 2) % 3;
    std::map<std::pair<int, int>, std::vector<std::pair<int, double>>> columns;   // (u, v) -> (index along a, radiance x length)
    for (auto it = emission.cbeginValueOn(); it; ++it) {
        const double le = radiance(*it) * voxel_length;
        if (!(le > 0.0)) continue;
        const openvdb::CoordBBox box = it.getBoundingBox();   // a tile emits from each voxel it covers
        for (openvdb::Coord c = box.min(); c[u] <= box.max()[u]; ++c[u])
            for (c[v] = box.min()[v]; c[v] <= box.max()[v]; ++c[v])
                for (c[a] = box.min()[a]; c[a] <= box.max()[a]; ++c[a]) columns[{c[u], c[v]}].emplace_back(c[a], le);
    }
    const openvdb::CoordBBox reach = density.evalActiveVoxelBoundingBox();
    auto acc = density.getConstAccessor();
    const auto densityAt = [&](openvdb::Coord c) { return std::max(0.0f, acc.getValue(c)); };
    std::vector<double> sums;
    sums.reserve(columns.size());
    for (auto& [key, emitters] : columns) {
        // From the camera's side inward: each emitter behind the depth of the voxels before it.
        std::sort(emitters.begin(), emitters.end(), [&](const auto& p, const auto& q) { return view.camera_at_max ? p.first > q.first : p.first < q.first; });
        openvdb::Coord c;
        c[u] = key.first;
        c[v] = key.second;
        const int step = view.camera_at_max ? -1 : 1;
        int at = view.camera_at_max ? std::max(reach.max()[a], emitters.front().first) : std::min(reach.min()[a], emitters.front().first);
        double depth = 0.0, sum = 0.0;
        for (const auto& [index, le] : emitters) {
            for (; at != index; at += step) c[a] = at, depth += depth_per_density * densityAt(c);
            c[a] = index;
            const double tau = depth_per_density * densityAt(c);
            sum += le * std::exp(-depth) * (tau > 1e-6 ? -std::expm1(-tau) / tau : 1.0);
        }
        if (sum > 0.0) sums.push_back(sum);
    }
    return sums;
}

std::string decimalText(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

bool setsKey(const SceneOverrides& o, const std::string& prefix) {
    return std::any_of(o.sets.begin(), o.sets.end(), [&](const std::string& s) { return s.rfind(prefix, 0) == 0; });
}

}  // namespace

Scene quickScene(const std::string& vdb) {
    Scene s;
    s.volume().path = vdb;
    s.lights.push_back(defaultKeyLight());
    return s;
}

Scene completeQuickScene(Scene scene, const SceneOverrides& o, std::optional<int> frame, std::vector<std::string>& notes) {
    std::string file = scene.volume().path;
    if (scene.volume().frames && hasFramePattern(file)) {
        const FrameSet& frames = *scene.volume().frames;
        file = expandFramePattern(file, frame.value_or(frames.at(frames.count() / 2)));
    }
    const LoadedVolume volume = placedVolume(loadVolume(file, scene.volume()), volumePlacement(scene.volume(), frame));
    const glm::mat3 view_frame = viewFrameOf(scene, volume);
    notes.push_back("quick form: up axis " +
                    (scene.volume().up == UpAxis::Auto ? volume.up.reason : signedAxisName(view_frame[1]) + " (volume.up)"));
    if (o.lights.empty() && !setsKey(o, "lights")) scene.lights = {defaultKeyLight(view_frame)};

    const ViewAxis view = viewAxis(volume.index_to_world, view_frame);
    const int axis = view.axis;
    if (!o.density_scale && !setsKey(o, "material")) {
        const double median = quantile(columnSums(*volume.density, axis, [](float v) { return double(v); }), 0.5);
        if (median > 0.0) {
            scene.volume().material.density_units = DensityUnits::Voxel;
            scene.volume().material.density_scale = float(std::min(double(kQuickOpticalDepth) / median, 3.0e38));
            notes.push_back("quick form: density_scale " + decimalText(scene.volume().material.density_scale) +
                            " per voxel: the median column along the view holds an optical depth of " +
                            decimalText(kQuickOpticalDepth) + " (--density-scale to change, in voxel units)");
        }
    }
    // The optical depth of one voxel along the view axis per unit of density, as the kernel scales
    // it (kernel_inputs.cpp: voxel units are per smallest edge).
    const double voxel_length = glm::length(glm::vec3(volume.index_to_world[axis]));
    double smallest_edge = voxel_length;
    for (int a = 0; a < 3; ++a) smallest_edge = std::min(smallest_edge, double(glm::length(glm::vec3(volume.index_to_world[a]))));
    const double depth_per_density = double(scene.volume().material.density_scale) *
                                     (scene.volume().material.density_units == DensityUnits::Voxel ? voxel_length / smallest_edge : voxel_length);
    for (size_t e = 0; e < scene.volume().emission.size() && !setsKey(o, "emission"); ++e) {
        EmissionSource& source = scene.volume().emission[e];
        if (source.kind != EmissionKind::Blackbody) continue;
        const glm::mat3 xyz(1.0f);   // luminance is Y
        const auto radiance = [&](float v) { return double(emissionRadiance(source, v, xyz).y); };
        // Grids on other voxels than the density's: the columns' emission before absorption.
        const double p99 = quantile(volume.density->transform() == volume.emission[e]->transform()
                                        ? transmittedColumnEmission(*volume.density, *volume.emission[e], view, depth_per_density, voxel_length, radiance)
                                        : columnSums(*volume.emission[e], axis, [&](float v) { return radiance(v) * voxel_length; }),
                                    0.99);
        if (p99 > 0.0) {
            source.intensity = float(source.intensity / p99);
            notes.push_back("quick form: blackbody intensity " + decimalText(source.intensity) +
                            ": 99% of the columns along the view bring at most 1 to the camera through the smoke (render.exposure to brighten)");
        }
    }
    return scene;
}

}  // namespace voxlux
