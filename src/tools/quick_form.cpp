#include "tools/quick_form.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// The index axis closest to the world direction the default camera looks from.
int viewAxis(const glm::mat4& index_to_world, int up_axis) {
    const glm::vec3 back = upFrame(up_axis)[2];
    int best = 0;
    float best_cos = -1.0f;
    for (int a = 0; a < 3; ++a) {
        const float c = std::abs(glm::dot(glm::normalize(glm::vec3(index_to_world[a])), back));
        if (c > best_cos) best_cos = c, best = a;
    }
    return best;
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
    s.volume.path = vdb;
    s.lights.push_back(defaultKeyLight());
    return s;
}

Scene completeQuickScene(Scene scene, const SceneOverrides& o, std::optional<int> frame, std::vector<std::string>& notes) {
    std::string file = scene.volume.path;
    if (scene.volume.frames && hasFramePattern(file)) {
        const FrameSet& frames = *scene.volume.frames;
        file = expandFramePattern(file, frame.value_or(frames.at(frames.count() / 2)));
    }
    const LoadedVolume volume = loadVolume(file, scene.volume, scene.emission);
    const int up = upAxisOf(scene, volume);
    const char* axis_names[] = {"x", "y", "z"};
    notes.push_back(std::string("quick form: up axis ") +
                    (scene.volume.up == UpAxis::Auto ? volume.up.reason : std::string(axis_names[up]) + " (volume.up)"));
    if (o.lights.empty() && !setsKey(o, "lights")) scene.lights = {defaultKeyLight(up)};

    const int axis = viewAxis(volume.index_to_world, up);
    if (!o.density_scale && !setsKey(o, "material")) {
        const double median = quantile(columnSums(*volume.density, axis, [](float v) { return double(v); }), 0.5);
        if (median > 0.0) {
            scene.material.density_units = DensityUnits::Voxel;
            scene.material.density_scale = float(std::min(double(kQuickOpticalDepth) / median, 3.0e38));
            notes.push_back("quick form: density_scale " + decimalText(scene.material.density_scale) +
                            " per voxel: the median column along the view holds an optical depth of " +
                            decimalText(kQuickOpticalDepth) + " (--density-scale to change, in voxel units)");
        }
    }
    const double voxel_length = glm::length(glm::vec3(volume.index_to_world[axis]));
    for (size_t e = 0; e < scene.emission.size() && !setsKey(o, "emission"); ++e) {
        EmissionSource& source = scene.emission[e];
        if (source.kind != EmissionKind::Blackbody) continue;
        const glm::mat3 xyz(1.0f);   // luminance is Y
        const double p99 = quantile(columnSums(*volume.emission[e], axis,
                                               [&](float v) { return double(emissionRadiance(source, v, xyz).y) * voxel_length; }),
                                    0.99);
        if (p99 > 0.0) {
            source.intensity = float(source.intensity / p99);
            notes.push_back("quick form: blackbody intensity " + decimalText(source.intensity) +
                            ": 99% of the columns along the view emit at most 1 (render.exposure to brighten)");
        }
    }
    return scene;
}

}  // namespace voxlux
