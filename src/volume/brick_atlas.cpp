#include "volume/brick_atlas.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numeric>

#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "volume/brick_set.h"
#include "vx_prelude.h"

namespace voxlux {
namespace {

constexpr int kStride = VX_BRICK_STRIDE;
constexpr int kVoxels = VX_BRICK_VOXELS;

// The bricks to store: those holding active values, plus their neighbours on the - side, whose
// + apron reaches into them (without those, the filter's ramp into a data brick from an empty
// one would be skipped by the march). Under motion blur, also the velocity's bricks within
// `motion_reach` of those: where the moving medium can be looked up from.
std::vector<glm::ivec3> bricksToStore(const LoadedVolume& v, int motion_reach, std::vector<glm::ivec3>& active) {
    collectBricks(v.density->tree(), active, v.file);
    for (const auto& e : v.emission) collectBricks(e->tree(), active, v.file);
    if (v.color) collectBricks(v.color->tree(), active, v.file);
    uniqueBricks(active);
    if (v.velocity && motion_reach > 0) {
        std::vector<glm::ivec3> moving;
        collectBricks(v.velocity->tree(), moving, v.file);
        uniqueBricks(moving);
        const std::vector<char> reached = bricksWithinReach(moving, active, motion_reach);
        for (size_t i = 0; i < moving.size(); ++i)
            if (reached[i]) active.push_back(moving[i]);
        uniqueBricks(active);
    }
    std::vector<glm::ivec3> all;
    all.reserve(active.size() * 2);
    for (const auto& b : active)
        for (int i = 0; i < 8; ++i) all.push_back(b - glm::ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    uniqueBricks(all);
    if (all.size() > kMaxBricks)
        throw InputError(v.file + ": " + std::to_string(all.size()) + " bricks exceed the limit of " +
                         std::to_string(kMaxBricks));
    // The kernel indexes the atlas with 32-bit ints: a vector channel's 3 floats a voxel bound it.
    if ((v.color || v.velocity) && all.size() * kVoxels * 3 > size_t(INT32_MAX))
        throw InputError(v.file + ": " + std::to_string(all.size()) + " bricks with a vector grid (" +
                         (v.color ? "colour" : "velocity") + ") exceed the limit of " +
                         std::to_string(size_t(INT32_MAX) / (kVoxels * 3)));
    return all;
}

// Fills one brick's 9^3 block of a scalar grid, replacing unusable values. Interior voxels of a
// leaf are copied from its buffer; the apron and tile-covered voxels go through the accessor.
template <typename Accessor>
void fillScalar(Accessor& acc, const glm::ivec3& b, float* dst, SanitizeCounts& fixes) {
    const openvdb::Coord origin(b.x * 8, b.y * 8, b.z * 8);
    const auto* leaf = acc.probeConstLeaf(origin);
    for (int z = 0; z < kStride; ++z)
        for (int y = 0; y < kStride; ++y)
            for (int x = 0; x < kStride; ++x) {
                const openvdb::Coord c = origin.offsetBy(x, y, z);
                const bool interior = x < 8 && y < 8 && z < 8;
                float value;
                bool active;
                if (interior && leaf) {
                    const auto i = leaf->coordToOffset(c);
                    value = leaf->getValue(i);
                    active = leaf->isValueOn(i);
                } else {
                    active = acc.probeValue(c, value);
                }
                if (!std::isfinite(value)) {
                    value = 0.0f;
                    fixes.non_finite += interior && active;
                } else if (value < 0.0f) {
                    value = 0.0f;
                    fixes.negative += interior && active;
                }
                dst[(z * kStride + y) * kStride + x] = value;
            }
}

// How fillVector treats a vector grid's values.
enum class VectorKind {
    Colour,     // components clamped to [0, 1]
    Velocity,   // inactive voxels read 0: the values maxSpeed bounds (a staggered grid's inactive
                // faces were never centred)
};

// Fills one brick's 9^3 block of a vector grid, 3 floats a voxel; non-finite components become 0.
template <typename Accessor>
void fillVector(Accessor& acc, const glm::ivec3& b, float* dst, SanitizeCounts& fixes, VectorKind kind) {
    const bool unit = kind == VectorKind::Colour;
    const openvdb::Coord origin(b.x * 8, b.y * 8, b.z * 8);
    for (int z = 0; z < kStride; ++z)
        for (int y = 0; y < kStride; ++y)
            for (int x = 0; x < kStride; ++x) {
                openvdb::Vec3s v;
                const bool active = acc.probeValue(origin.offsetBy(x, y, z), v);
                if (!active && kind == VectorKind::Velocity) v = openvdb::Vec3s(0.0f);
                const bool counted = active && x < 8 && y < 8 && z < 8;
                float* out = dst + 3 * ((z * kStride + y) * kStride + x);
                for (int k = 0; k < 3; ++k) {
                    float c = v[k];
                    if (!std::isfinite(c)) { c = 0.0f; fixes.non_finite += counted; }
                    else if (unit && c < 0.0f) { c = 0.0f; fixes.negative += counted; }
                    else if (unit && c > 1.0f) { c = 1.0f; fixes.above_one += counted; }
                    out[k] = c;
                }
            }
}

void addCounts(SanitizeCounts& into, const SanitizeCounts& c) {
    into.non_finite += c.non_finite;
    into.negative += c.negative;
    into.above_one += c.above_one;
}

}  // namespace

size_t BrickAtlas::bytes() const {
    return coords.size() * sizeof(glm::ivec3) +
           (density.size() + emission.size() + color.size() + transport.size() + surface.size() + velocity.size()) * sizeof(float) +
           density_range.size() * sizeof(glm::vec2) + emission_max.size() * sizeof(float);
}

float BrickAtlas::emissionGridMax(size_t source) const {
    const auto first = emission_max.begin() + std::ptrdiff_t(source * slots());
    return std::accumulate(first, first + std::ptrdiff_t(slots()), 0.0f, [](float a, float b) { return std::max(a, b); });
}

BrickAtlas buildBrickAtlas(const LoadedVolume& v, int motion_reach) {
    BrickAtlas atlas;
    atlas.index_to_world = v.index_to_world;
    atlas.active_voxels = v.density->activeVoxelCount();
    atlas.motion_reach = v.velocity ? motion_reach : 0;
    std::vector<glm::ivec3> active;
    std::vector<glm::ivec3> candidates = bricksToStore(v, atlas.motion_reach, active);

    const size_t n = candidates.size(), sources = v.emission.size();
    std::vector<float> density(n * kVoxels), emission(sources * n * kVoxels), color(v.color ? n * kVoxels * 3 : 0),
        transport(v.transport ? n * kVoxels * 3 : 0), surface(v.surface ? n * kVoxels : 0), velocity(v.velocity ? n * kVoxels * 3 : 0);
    struct Fixes {
        SanitizeCounts density, color, velocity;
        SanitizeCounts classified;   // transport colour and surface weight: classified in range, never fixed
        std::vector<SanitizeCounts> emission;
    };
    tbb::combinable<Fixes> fixes([&] { return Fixes{{}, {}, {}, {}, std::vector<SanitizeCounts>(sources)}; });
    using FloatAcc = openvdb::FloatGrid::ConstAccessor;
    tbb::enumerable_thread_specific<FloatAcc> densityAcc([&] { return v.density->getConstAccessor(); });
    tbb::enumerable_thread_specific<std::vector<FloatAcc>> emissionAcc([&] {
        std::vector<FloatAcc> accs;
        for (const auto& e : v.emission) accs.push_back(e->getConstAccessor());
        return accs;
    });
    tbb::enumerable_thread_specific<std::unique_ptr<openvdb::Vec3SGrid::ConstAccessor>> colorAcc, transportAcc, velocityAcc;
    tbb::enumerable_thread_specific<std::unique_ptr<FloatAcc>> surfaceAcc;

    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 16), [&](const tbb::blocked_range<size_t>& r) {
        Fixes& f = fixes.local();
        auto& dacc = densityAcc.local();
        auto& eacc = emissionAcc.local();
        for (size_t i = r.begin(); i != r.end(); ++i) {
            fillScalar(dacc, candidates[i], &density[i * kVoxels], f.density);
            for (size_t e = 0; e < sources; ++e)
                fillScalar(eacc[e], candidates[i], &emission[(e * n + i) * kVoxels], f.emission[e]);
            if (v.color) {
                auto& acc = colorAcc.local();
                if (!acc) acc = std::make_unique<openvdb::Vec3SGrid::ConstAccessor>(v.color->getConstAccessor());
                fillVector(*acc, candidates[i], &color[i * kVoxels * 3], f.color, VectorKind::Colour);
            }
            if (v.transport) {
                auto& acc = transportAcc.local();
                if (!acc) acc = std::make_unique<openvdb::Vec3SGrid::ConstAccessor>(v.transport->getConstAccessor());
                fillVector(*acc, candidates[i], &transport[i * kVoxels * 3], f.classified, VectorKind::Colour);
            }
            if (v.surface) {
                auto& acc = surfaceAcc.local();
                if (!acc) acc = std::make_unique<FloatAcc>(v.surface->getConstAccessor());
                fillScalar(*acc, candidates[i], &surface[i * kVoxels], f.classified);
            }
            if (v.velocity) {
                auto& acc = velocityAcc.local();
                if (!acc) acc = std::make_unique<openvdb::Vec3SGrid::ConstAccessor>(v.velocity->getConstAccessor());
                fillVector(*acc, candidates[i], &velocity[i * kVoxels * 3], f.velocity, VectorKind::Velocity);
            }
        }
    });
    atlas.emission_sources = sources;
    atlas.emission_fixes.resize(sources);
    fixes.combine_each([&](const Fixes& f) {
        addCounts(atlas.density_fixes, f.density);
        addCounts(atlas.color_fixes, f.color);
        addCounts(atlas.velocity_fixes, f.velocity);
        for (size_t e = 0; e < sources; ++e) addCounts(atlas.emission_fixes[e], f.emission[e]);
    });

    // Keep every brick with active values; keep a - side neighbour only if its block is non-zero.
    std::vector<glm::vec2> range(n);
    std::vector<float> emissionMax(sources * n);
    std::vector<char> keep(n);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
        const float* d = &density[i * kVoxels];
        glm::vec2 mm(d[0], d[0]);
        for (int k = 1; k < kVoxels; ++k) mm = glm::vec2(std::min(mm.x, d[k]), std::max(mm.y, d[k]));
        range[i] = mm;
        float any = 0.0f;
        for (size_t e = 0; e < sources; ++e) {
            const float* em = &emission[(e * n + i) * kVoxels];
            emissionMax[e * n + i] = *std::max_element(em, em + kVoxels);
            any = std::max(any, emissionMax[e * n + i]);
        }
        keep[i] = std::binary_search(active.begin(), active.end(), candidates[i], brickLess) || mm.y > 0.0f || any > 0.0f;
    });

    // Compact in place (slot j <= candidate i, channel by channel), so the atlas never exists
    // twice in memory.
    std::vector<size_t> kept;
    for (size_t i = 0; i < n; ++i)
        if (keep[i]) kept.push_back(i);
    const size_t slots = kept.size();
    for (size_t j = 0; j < slots; ++j) {
        const size_t i = kept[j];
        atlas.coords.push_back(candidates[i]);
        atlas.density_range.push_back(range[i]);
        std::copy_n(&density[i * kVoxels], kVoxels, &density[j * kVoxels]);
        if (v.color) std::copy_n(&color[i * kVoxels * 3], kVoxels * 3, &color[j * kVoxels * 3]);
        if (v.transport) std::copy_n(&transport[i * kVoxels * 3], kVoxels * 3, &transport[j * kVoxels * 3]);
        if (v.surface) std::copy_n(&surface[i * kVoxels], kVoxels, &surface[j * kVoxels]);
        if (v.velocity) std::copy_n(&velocity[i * kVoxels * 3], kVoxels * 3, &velocity[j * kVoxels * 3]);
    }
    for (size_t e = 0; e < sources; ++e)
        for (size_t j = 0; j < slots; ++j) {
            atlas.emission_max.push_back(emissionMax[e * n + kept[j]]);
            std::copy_n(&emission[(e * n + kept[j]) * kVoxels], kVoxels, &emission[(e * slots + j) * kVoxels]);
        }
    density.resize(slots * kVoxels);
    emission.resize(sources * slots * kVoxels);
    color.resize(v.color ? slots * kVoxels * 3 : 0);
    transport.resize(v.transport ? slots * kVoxels * 3 : 0);
    surface.resize(v.surface ? slots * kVoxels : 0);
    velocity.resize(v.velocity ? slots * kVoxels * 3 : 0);
    atlas.density = std::move(density);
    atlas.emission = std::move(emission);
    atlas.color = std::move(color);
    atlas.transport = std::move(transport);
    atlas.surface = std::move(surface);
    atlas.velocity = std::move(velocity);
    return atlas;
}

std::vector<std::string> sanitizeReport(const BrickAtlas& a, const LoadedVolume& v) {
    std::vector<std::string> out;
    auto report = [&](const SanitizeCounts& c, const openvdb::GridBase* g) {
        if (!c.any() || !g) return;
        std::string s = v.file + ": grid '" + g->getName() + "':";
        if (c.non_finite) s += " " + std::to_string(c.non_finite) + " NaN/Inf voxels set to 0;";
        if (c.negative) s += " " + std::to_string(c.negative) + " negative voxels set to 0;";
        if (c.above_one) s += " " + std::to_string(c.above_one) + " colour components above 1 set to 1;";
        s.pop_back();
        out.push_back(s);
    };
    report(a.density_fixes, v.density.get());
    for (size_t e = 0; e < a.emission_sources; ++e) report(a.emission_fixes[e], v.emission[e].get());
    report(a.color_fixes, v.color.get());
    report(a.velocity_fixes, v.velocity.get());
    return out;
}

}  // namespace voxlux
