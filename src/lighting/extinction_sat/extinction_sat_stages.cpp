#include "lighting/extinction_sat/extinction_sat_stages.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

#include "kernel/medium_inputs.h"
#include "core/huge_pages.h"
#include "kernel/kernel_backend.h"
#include "kernel/kernel_inputs.h"
#include "volume/volume_stages.h"

namespace voxlux {
namespace {

bool needsAmbientOcclusion(const Scene& s) { return s.effects.ambient_occlusion && enabledLightCount(s, true) > 0; }
bool needsConeShadows(const Scene& s) { return s.effects.shadows == ShadowMethod::SatCone && enabledLightCount(s, false) > 0; }

StageActivity satActivity(const Scene& s, const std::string& what) {
    if (s.render.method == RenderMethod::Reference)
        return {false, kReferenceComputesAllLight};
    if (!needsAmbientOcclusion(s) && !needsConeShadows(s)) {
        std::string why = "skipped: no effect in the scene needs a precomputed light cache";
        if (s.effects.ambient_occlusion) why += " (ambient_occlusion is on but no ambient light is in the scene)";
        return {false, why};
    }
    return {true, what};
}

// Channels the cache holds for `scene` with `lights` packed (enabled, non-ambient) lights.
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

// The colour-bleeding weight the light grid carries (0: extinction only).
float bleedingOf(const Scene& s) { return needsAmbientOcclusion(s) && s.effects.color_bleeding > 0.0f ? s.effects.color_bleeding : 0.0f; }

// Distinct across every stage in the process, so a backend shared by several renderers never
// mistakes one SAT for another.
uint64_t nextSatGeneration() {
    static std::atomic<uint64_t> next{1};
    return next++;
}

// The link sets whose lights' cones need a SAT of their own: those only some volumes shadow.
std::vector<bool> ownShadowSats(const Scene& s) {
    std::vector<bool> own;
    if (needsConeShadows(s))
        for (const LinkSet& set : lightLinks(s).sets) own.push_back(set.shadows.has_value());
    return own;
}

}  // namespace

bool lightCacheRuns(const Scene& scene) { return satActivity(scene, "").runs; }

StageReads SatStage::reads() const {
    // What its grid holds beyond the shared extinction (bleeding) and what the SAT and cache cost
    // (planes, and a channel per light), which may lower its resolution below the shared grid's.
    return {withPlacementKeys({"/effects/color_bleeding", "/effects/ambient_occlusion?", "/effects/shadows", "/lights/*/type",
                               "/lights/*/enabled", "/input/light_links/shadows", "/render/backend"})};
}

StageActivity SatStage::activity(const Scene& s) const {
    return satActivity(s, std::string("integer summed-area table of the light grid") +
                              (bleedingOf(s) > 0.0f ? ", with three colour-bleeding planes" : ""));
}

void SatStage::release() {
    own_grid_ = LightGrid{};
    sat_ = SummedVolume{};
    linked_sats_.clear();
    linked_generations_.clear();
}

const SummedVolume& SatStage::satOf(int link) const {
    return size_t(link) < linked_sats_.size() && linked_sats_[size_t(link)].planes > 0 ? linked_sats_[size_t(link)] : sat_;
}

uint64_t SatStage::generationOf(int link) const {
    return size_t(link) < linked_sats_.size() && linked_sats_[size_t(link)].planes > 0 ? linked_generations_[size_t(link)] : generation_;
}

void SatStage::run(StageRun& run) {
    release();
    const Scene& scene = run.scene({"/effects/color_bleeding", "/effects/ambient_occlusion?", "/effects/shadows",
                                    "/effects/light_resolution", "/effects/light_memory_mb", "/lights", "/volumes/*/material",
                                    "/volumes/*/transform"});
    const float bleeding = bleedingOf(scene);
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame());
    const glm::vec3 extent = lightGridExtent(inputs);
    const std::vector<bool> own_sats = ownShadowSats(scene);
    std::string warning;
    // A link set's own SAT costs as one more plane.
    resolution_ = fitLightResolution(extent, cappedLightResolution(extent, scene.effects.light_resolution),
                                     (bleeding > 0.0f ? 4 : 1) + int(std::count(own_sats.begin(), own_sats.end(), true)), cacheLayout(scene, enabledLightCount(scene, false)).channels,
                                     size_t(scene.effects.light_memory_mb) << 20, warning);
    if (!warning.empty()) run.warnings.push_back(warning);
    if (resolution_ != shared_.resolution() || (bleeding > 0.0f && !uniformAlbedo(inputs))) {
        own_grid_ = buildLightGrid(inputs, resolution_, {true, bleeding});
        if (own_grid_.clamped_cells && resolution_ != shared_.resolution()) run.warnings.push_back(clampedCellsWarning(own_grid_));
    } else if (bleeding > 0.0f) {
        own_grid_ = withUniformBleeding(shared_.grid(), inputs.params.albedo, bleeding);
    }
    generation_ = nextSatGeneration();
    passes_.on(run.backend).buildSat(grid(), sat_);
    linked_sats_.resize(own_sats.size());
    linked_generations_.assign(own_sats.size(), 0);
    for (size_t link = 0; link < own_sats.size(); ++link) {
        if (!own_sats[link]) continue;
        const LightGrid shadows = buildLightGrid(inputs, resolution_, {.link = int(link)});
        linked_generations_[link] = nextSatGeneration();
        passes_.on(run.backend).buildSat(shadows, linked_sats_[link]);
    }
}

StageReads LightCacheStage::reads() const {
    return {withPlacementKeys({"/effects/ambient_occlusion", "/effects/color_bleeding", "/effects/cone", "/effects/shadows",
                               "/lights/*/type", "/lights/*/enabled", "/lights/*/position", "/lights/*/direction",
                               "/input/light_links/of_light", "/input/light_links/shadows", "/render/backend"})};
}

StageActivity LightCacheStage::activity(const Scene& s) const {
    const Effects& fx = s.effects;
    std::vector<std::string> passes;
    if (needsAmbientOcclusion(s))
        passes.push_back("ambient occlusion, " + std::to_string(fx.ambient_occlusion->shells) + " shells" +
                         (fx.color_bleeding > 0 ? " with colour bleeding" : ""));
    if (needsConeShadows(s)) {
        const int lights = enabledLightCount(s, false);
        char cone[96];
        std::snprintf(cone, sizeof cone, "%d shadow cone%s of %d cuboids (%g deg)", lights, lights == 1 ? "" : "s",
                      fx.cone.samples, double(fx.cone.angle));
        passes.push_back(cone);
    }
    std::string what;
    for (const auto& p : passes) what += (what.empty() ? "" : ", ") + p;
    if (fx.ambient_occlusion && !needsAmbientOcclusion(s)) what += " (ambient_occlusion is on but no ambient light is in the scene)";
    if (fx.color_bleeding > 0 && !needsAmbientOcclusion(s)) what += " (color_bleeding needs ambient occlusion)";
    return satActivity(s, what);
}

void LightCacheStage::lightTheMarch(const Scene& scene, MarchLighting& lighting) const {
    if (cache_.channels <= 0) return;
    kernel::VxSatMarch& b = lighting.blocks.extinction_sat;
    b.world_to_cache = cache_.world_to_cache;
    b.cache_dims = cache_.dims;
    b.cache_floats = cache_.channels;
    b.ao_channel = std::max(cache_.ambient_channel, 0);
    b.ao_channels = cache_.ambient_channel >= 0 ? cache_.ambient_width : 0;
    b.shadow_channel = std::max(cache_.shadow_channel, 0);
    b.shadows = scene.effects.shadows == ShadowMethod::SatCone && cache_.shadow_channel >= 0 ? 1 : 0;
    lighting.setArray("LightCache", cache_.values.data(), cache_.values.size() * sizeof(float));
}

void LightCacheStage::release() {
    cache_ = LightCache{};
    channel_keys_.clear();
}

void LightCacheStage::run(StageRun& run) {
    const Scene& scene = run.scene({"/effects/ambient_occlusion", "/effects/color_bleeding", "/effects/cone", "/effects/shadows",
                                    "/lights", "/volumes/*/material", "/volumes/*/transform"});
    const Effects& fx = scene.effects;
    const LightGrid& grid = sat_.grid();
    const KernelInputs inputs = mediumInputs(scene, brick_, classify_, volumes_, run.scene.frame());
    LightCache layout = cacheLayout(scene, int(inputs.lights.size()));
    // The cache is kept as it is while its layout is, so unchanged channels survive.
    const glm::mat4 light_to_world = inputs.index_to_world * grid.lightToIndex();
    layout.dims = grid.dims;
    const bool same_layout = cache_.channels == layout.channels && cache_.ambient_channel == layout.ambient_channel &&
                             cache_.ambient_width == layout.ambient_width && cache_.shadow_channel == layout.shadow_channel &&
                             cache_.dims == layout.dims && !channel_keys_.empty();
    if (!same_layout) {
        assignInHugePages(layout.values, grid.cells() * size_t(layout.channels), 0.0f);
        cache_ = std::move(layout);
        channel_keys_.assign(size_t(cache_.channels), "");
    }
    cache_.world_to_cache = glm::inverse(light_to_world);   // a grid of the same dims may have moved

    const SummedVolume& sat = sat_.sat();
    SatPasses& passes = passes_.on(run.backend);
    LightPass pass;
    pass.lights = &inputs.lights;
    pass.sat = &sat;
    pass.sat_generation = sat_.generation();
    pass.needed = &grid.needed;
    kernel::VxSatParams& S = pass.params;
    S.light_to_world = light_to_world;
    S.world_to_light = cache_.world_to_cache;
    S.dims = grid.dims;
    S.planes = sat.planes;
    S.quantum = sat.quantum;
    S.cache_floats = cache_.channels;
    const float cell_world = cellWorldSize(light_to_world);
    S.cone_tan = std::tan(glm::radians(fx.cone.angle));
    S.cone_cuboids = fx.cone.samples;
    S.cone_growth = fx.cone.growth;
    S.cone_growth_total = std::pow(1.0f + fx.cone.growth, float(fx.cone.samples));
    const std::string cone_key = hashBytes(glm::vec4(S.cone_tan, float(S.cone_cuboids), S.cone_growth, S.cone_growth_total));
    // Every channel is computed from a SAT (a linked light's from its set's); what else it depends on
    // is added per channel.
    const std::string backend = run.scene.value("/render/backend").dump();
    const auto sat_key = [&](uint64_t generation) { return std::to_string(generation) + "|" + backend; };

    if (cache_.ambient_channel >= 0) {
        const AmbientOcclusion& ao = *fx.ambient_occlusion;
        // Beyond the grid's longest side a larger radius changes nothing (and would overflow k_i).
        const float longest = float(std::max({grid.dims.x, grid.dims.y, grid.dims.z}));
        const float radius_cells =
            std::min(ao.radius > 0.0f ? ao.radius / cell_world : 0.06f * float(sat_.resolution()), longest);
        S.shells = ao.shells;
        S.shell_radius = radius_cells;
        S.cell_world = cell_world;
        S.light = -1;
        bool ran = false;
        for (int i = 0; i < cache_.ambient_width; ++i) {
            S.ao_plane = cache_.ambient_width == 3 ? i + 1 : 0;  // SAT plane: extinction or bleeding RGB
            const glm::vec4 shells(float(S.shells), S.shell_radius, S.cell_world, float(S.ao_plane));
            ran |= fillChannel(pass, cache_.ambient_channel + i, sat_key(sat_.generation()) + "|ao|" + hashBytes(shells), passes);
        }
        if (!ran) run.reused.push_back("ambient");
    }

    if (cache_.shadow_channel >= 0) {
        for (int i = 0; i < int(inputs.lights.size()); ++i) {
            // Only where the light is (or, directional, where it points) shapes its cone: colour,
            // intensity and spot angles leave the cached optical depth as it is.
            const kernel::VxLight& light = inputs.lights[size_t(i)];
            const glm::vec4 where = light.type == VX_LIGHT_DIRECTIONAL ? glm::vec4(light.direction, 0.0f) : glm::vec4(light.position, 1.0f);
            S.light = i;
            // A linked light's cone reads the SAT of the volumes that shadow it.
            pass.sat = &sat_.satOf(light.link_set);
            pass.sat_generation = sat_.generationOf(light.link_set);
            S.planes = pass.sat->planes;
            S.quantum = pass.sat->quantum;
            if (!fillChannel(pass, cache_.shadow_channel + i, sat_key(pass.sat_generation) + "|cone|" + cone_key + hashBytes(where), passes))
                run.reused.push_back("shadow of light " + std::to_string(i));
        }
    }
}

bool LightCacheStage::fillChannel(LightPass& pass, int channel, const std::string& key, SatPasses& passes) {
    if (channel_keys_[size_t(channel)] == key) return false;
    channel_keys_[size_t(channel)].clear();  // stays cleared if the pass throws
    pass.params.channel = channel;
    passes.fillLightChannel(pass, cache_);
    channel_keys_[size_t(channel)] = key;
    return true;
}

}  // namespace voxlux
