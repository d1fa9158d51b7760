#include "light_stage.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "scene_json.h"

namespace voxlux {
namespace {

// Channels the cache holds for `scene` with `lights` packed (non-ambient) lights.
LightCache cacheLayout(const Scene& scene, int lights) {
    LightCache c;
    if (needsAmbientOcclusion(scene)) {
        c.ambient_channel = 0;
        c.ambient_width = scene.effects.color_bleeding > 0.0f ? 3 : 1;
        c.channels = c.ambient_width;
    }
    if (needsConeShadows(scene)) {
        c.shadow_channel = c.channels;
        c.channels += lights;
    }
    return c;
}

// Distinct across every stage in the process, so a backend shared by several renderers never
// mistakes one SAT for another.
uint64_t nextSatGeneration() {
    static std::atomic<uint64_t> next{1};
    return next++;
}

}  // namespace

void LightStage::update(const Scene& scene, const std::string& volume_key, KernelInputs& inputs,
                        KernelBackend& backend, StageTimes& times, std::vector<std::string>& reused,
                        std::vector<std::string>& warnings) {
    const Effects& fx = scene.effects;
    LightCache layout = cacheLayout(scene, int(inputs.lights.size()));
    const int planes = fx.color_bleeding > 0.0f && layout.ambient_channel >= 0 ? 4 : 1;
    const float bleeding = planes == 4 ? fx.color_bleeding : 0.0f;

    const glm::vec3 extent = occupiedExtent(inputs);
    const int wanted = cappedLightResolution(extent, fx.light_resolution);
    std::string warning;
    const int resolution = fitLightResolution(extent, wanted, planes, layout.channels,
                                              size_t(fx.light_memory_mb) << 20, warning);
    if (!warning.empty()) warnings.push_back(warning);
    const nlohmann::json scene_json = sceneToJson(scene);
    const std::string grid_key = volume_key + "|" + scene_json["material"].dump() + "|" + std::to_string(resolution) +
                                 "|" + std::to_string(bleeding) + "|" + occupiedBoxKey(inputs);
    StageClock clock(times);
    if (grid_key == grid_key_) {
        reused.push_back("light_grid");
        reused.push_back("sat");
    } else {
        rebuildGrid(inputs, resolution, bleeding, backend, clock, warnings);
        grid_key_ = grid_key;
    }

    // The cache: kept as it is when its layout is unchanged, so unchanged channels survive.
    const glm::mat4 light_to_world = inputs.atlas->index_to_world * grid_.lightToIndex();
    layout.dims = grid_.dims;
    layout.world_to_cache = glm::inverse(light_to_world);
    const bool same_layout = cache_.channels == layout.channels && cache_.ambient_width == layout.ambient_width &&
                             cache_.dims == layout.dims && !channel_keys_.empty();
    if (!same_layout) {
        layout.values.assign(grid_.cells() * size_t(layout.channels), 0.0f);
        cache_ = std::move(layout);
        channel_keys_.assign(size_t(cache_.channels), "");
    }

    LightPass pass;
    pass.lights = &inputs.lights;
    pass.sat = &sat_;
    pass.sat_generation = sat_generation_;
    pass.needed = &grid_.needed;
    kernel::VxSatParams& S = pass.params;
    S.light_to_world = light_to_world;
    S.world_to_light = cache_.world_to_cache;
    S.dims = glm::ivec4(grid_.dims, sat_.planes);
    S.quantum = sat_.quantum;
    S.pass.z = cache_.channels;
    const float cell_world = cellWorldSize(light_to_world);
    S.cone = glm::vec4(std::tan(glm::radians(fx.cone.angle)), float(fx.cone.samples), fx.cone.growth,
                       std::pow(1.0f + fx.cone.growth, float(fx.cone.samples)));

    if (cache_.ambient_channel >= 0) {
        const AmbientOcclusion& ao = *fx.ambient_occlusion;
        // Beyond the grid's longest side a larger radius changes nothing (and would overflow k_i).
        const float longest = float(std::max({grid_.dims.x, grid_.dims.y, grid_.dims.z}));
        const float radius_cells = std::min(ao.radius > 0.0f ? ao.radius / cell_world : 0.06f * float(resolution), longest);
        S.shells = glm::vec4(float(ao.shells), radius_cells, cell_world, 0.0f);
        S.pass.x = -1;
        const std::string key = grid_key_ + "|ao|" + std::to_string(ao.shells) + "|" + std::to_string(radius_cells);
        bool ran = false;
        clock("ambient", [&] {
            for (int i = 0; i < cache_.ambient_width; ++i) {
                S.shells.w = float(cache_.ambient_width == 3 ? i + 1 : 0);  // SAT plane: extinction or bleeding RGB
                ran |= fillChannel(pass, cache_.ambient_channel + i, key + "|" + std::to_string(i), backend);
            }
        });
        if (!ran) {
            times.pop_back();
            reused.push_back("ambient");
        }
    }

    if (cache_.shadow_channel >= 0) {
        const std::string cone_key = grid_key_ + "|" + scene_json["effects"]["cone"].dump();
        int packed = 0;
        bool ran = false;
        clock("shadows", [&] {
            for (const auto& light : scene_json["lights"]) {
                if (light["type"] == "ambient") continue;
                S.pass.x = packed;
                // Only where the light is (or, directional, where it points) shapes its cone:
                // colour, intensity and spot angles leave the cached optical depth as it is.
                nlohmann::json where = {{"type", light["type"]}};
                if (light.contains("position")) where["position"] = light["position"];
                if (light["type"] == "directional") where["direction"] = light["direction"];
                if (fillChannel(pass, cache_.shadow_channel + packed, cone_key + "|" + where.dump(), backend)) ran = true;
                else reused.push_back("shadow of light " + std::to_string(packed));
                ++packed;
            }
        });
        if (!ran) times.pop_back();
    }

    auto& P = inputs.params;
    P.world_to_cache = cache_.world_to_cache;
    P.cache_dims = glm::ivec4(cache_.dims, cache_.channels);
    P.cache_map = glm::ivec4(cache_.ambient_channel, cache_.ambient_width, cache_.shadow_channel, 0);
    inputs.cache = cache_.values.data();
    inputs.cache_floats = cache_.values.size();
}

void LightStage::rebuildGrid(const KernelInputs& inputs, int resolution, float bleeding, KernelBackend& backend,
                             StageClock& clock, std::vector<std::string>& warnings) {
    grid_key_.clear();  // stays cleared if a pass throws
    channel_keys_.clear();
    grid_ = clock("light_grid", [&] { return buildLightGrid(inputs, resolution, bleeding); });
    if (grid_.clamped_cells) warnings.push_back(clampedCellsWarning(grid_));
    clock("sat", [&] { backend.buildSat(grid_, sat_); });
    sat_generation_ = nextSatGeneration();
}

bool LightStage::fillChannel(LightPass& pass, int channel, const std::string& key, KernelBackend& backend) {
    if (channel_keys_[size_t(channel)] == key) return false;
    channel_keys_[size_t(channel)].clear();  // stays cleared if the pass throws
    pass.params.pass.y = channel;
    backend.fillLightChannel(pass, cache_);
    channel_keys_[size_t(channel)] = key;
    return true;
}

}  // namespace voxlux
