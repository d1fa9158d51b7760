#include "reference/reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "core/progress.h"

#include "kernel/cpu_kernel_data.h"
#include "optics/environment_map.h"
#include "volume/brick_set.h"
#include "core/error.h"

namespace voxlux {
namespace {

using kernel::CpuKernelData;

// The tracker: the kernel bound to the inputs, and the extinction bounds of its slots. Rays are in
// world units; the kernel's brick DDA walks them in index space with t as world distance. Under
// motion blur a path has one time, and every lookup along it sees the medium at that time.
struct Tracker {
    CpuKernelData& k;
    const ExtinctionBounds& bounds;
    std::atomic<uint64_t>& opaque_segments;
    float time = 0.0f;    // the path's, frames from the frame's own (vx_motion.h)

    bool several() const { return k.P.volume_count > 0; }

    // One stretch of a walk, of constant majorant and minorant: a stored brick's (slot, brick),
    // whose points o + d * t are in index space; or, of several volumes, a stretch inside the same
    // volumes' boxes (slot -1), whose points o + d * t are in world space.
    struct Segment {
        int slot;
        glm::ivec3 brick;
        glm::vec3 o, d;
        float t, t_end, majorant, minorant;
    };

    // The medium at a tentative collision: the one volume's reconstruction at the path's time
    // (nothing where it came from no stored brick: all its values are 0), or the several volumes'
    // summed medium, shaded (its scattering and emission) unless `extinction_only` (shadow rays).
    struct Collision {
        std::optional<CpuKernelData::VxTaps> taps;
        CpuKernelData::VxMedium mixed{};
    };

    Collision medium(const Segment& s, float t, bool extinction_only = false, int link = VX_ALL_LINKS) const {
        Collision c;
        const glm::vec3 p = s.o + s.d * t;
        if (s.slot < 0) {
            bool inside = false;
            c.mixed = k.vx_volumes_medium(p, !extinction_only, time, link, inside);
            return c;
        }
        bool found = false;
        const CpuKernelData::VxTaps taps = k.vx_moved_taps(s.slot, s.brick, p, k.vx_motion_shift(s.slot, s.brick, p, time), found);
        if (found) c.taps = taps;
        return c;
    }
    // The collision a path scatters at: where a segment taken as opaque has no medium of the one
    // volume, any stored cell's (its albedo).
    Collision scattering(const Segment& s, float t, Collision c) const {
        if (s.slot >= 0 && !c.taps) c.taps = k.vx_taps_at(s.slot, s.brick, s.o + s.d * t);
        return c;
    }
    // Light linking: the scattering and g at world point x of the volumes link set `link`'s lights
    // light (vx_volumes_medium).
    CpuKernelData::VxMedium linked(glm::vec3 x, int link) const {
        bool inside = false;
        return k.vx_volumes_medium(x, true, time, link, inside);
    }
    // The extinction light meets (of several volumes, every volume's), and the share of it a
    // camera ray meets and the share that scatters colour (of several volumes, the visible ones';
    // a matte or a shadow-only volume only absorbs).
    float extinction(const Collision& c) const { return several() ? c.mixed.sigma : c.taps ? k.vx_extinction(*c.taps) : 0.0f; }
    float cameraExtinction(const Collision& c) const { return several() ? c.mixed.sigma_camera : extinction(c); }
    float visibleExtinction(const Collision& c) const { return several() ? c.mixed.sigma_visible : extinction(c); }
    glm::vec3 emission(const Collision& c) const { return several() ? c.mixed.emitted : c.taps ? k.vx_emission(*c.taps) : glm::vec3(0.0f); }
    // The albedo at a collision with extinction `sigma` (extinction(c) for a path's flights,
    // cameraExtinction(c) for the camera ray's).
    glm::vec3 albedo(const Collision& c, float sigma) const { return several() ? k.vx_medium_albedo(c.mixed, sigma) : k.vx_albedo(*c.taps); }
    float anisotropy(const Collision& c) const { return several() ? k.vx_medium_g(c.mixed) : k.P.anisotropy; }

    // Tentative collisions one brick's segment may take: m * length of them are expected, a
    // handful where the majorant is tight, 65536 at an optical-depth bound of 65536 in one brick
    // (where any light left is below a float's resolution of the image's values).
    static constexpr int kMaxSegmentEvents = 1 << 16;

    // The tentative collision after t at majorant m, or nothing when the majorant overflowed a
    // float (density 3e38: no step could leave t, and no event could collide) or the segment has
    // taken kMaxSegmentEvents. The medium is then opaque there: the caller stops, and the segment
    // is counted (a bias towards opaque, reported). A step below t's float resolution (density
    // 1e6 a hundred units from the camera) moves to the next float, so every event makes progress.
    std::optional<float> nextCollision(float t, float m, int events_here, ReferenceRng& rng) const {
        if (!std::isfinite(m) || events_here >= kMaxSegmentEvents) {
            ++opaque_segments;
            return std::nullopt;
        }
        return std::max(t - std::log(1.0f - rng.next()) / m, std::nextafter(t, INFINITY));
    }

    // Calls visit(segment) for each segment of non-zero majorant the ray crosses within [0, t_max),
    // in order, until visit returns false: the one volume's bricks, or several volumes' stretches.
    template <class Visit>
    void walk(glm::vec3 x, glm::vec3 w, float t_max, Visit&& visit) const {
        if (several()) return walkVolumes(x, w, t_max, visit);
        const glm::vec3 o = k.vx_to_index_point(x), d = k.vx_to_index_dir(w);
        float t0 = 0.0f, t1 = t_max;
        if (!k.vx_clip_to_bricks(o, d, t0, t1)) return;
        CpuKernelData::VxDda s = k.vx_dda_begin(o, d, t0, t1);
        const bool skips = k.vx_skips_regions();
        glm::ivec3 region = k.vx_no_region();
        k.vx_dda_skip_empty(s, region, skips);
        while (s.t < s.t_end) {
            const int slot = k.vx_page_lookup(s.brick);
            if (slot != VX_PAGE_EMPTY && bounds.majorant[slot] > 0.0f &&
                !visit(Segment{slot, s.brick, o, d, s.t, k.vx_dda_exit(s), bounds.majorant[slot], bounds.minorant[slot]}))
                return;
            k.vx_dda_next(s, region, skips);
        }
    }

    // Several volumes: the stretches between the points where the ray enters or leaves a volume's
    // box, each at the sum of the majorants of the volumes whose boxes hold it (a volume's majorant
    // is its largest extinction, ExtinctionBounds::volume_majorant), with no minorant.
    template <class Visit>
    void walkVolumes(glm::vec3 x, glm::vec3 w, float t_max, Visit&& visit) const {
        thread_local std::vector<std::pair<float, int>> ends;   // t, and volume + 1 entering or -(volume + 1) leaving
        ends.clear();
        for (int v = 0; v < k.P.volume_count; ++v) {
            const kernel::VxVolume V = k.vx_placed_volume(v);
            float a = 0.0f, b = t_max;
            if (bounds.volume_majorant[size_t(v)] > 0.0f &&
                k.vx_clip_to_box(glm::vec3(V.world_to_index * glm::vec4(x, 1.0f)), glm::vec3(V.world_to_index * glm::vec4(w, 0.0f)),
                                 k.vx_volume_lo(V), k.vx_volume_hi(V), a, b)) {
                ends.emplace_back(a, v + 1);
                ends.emplace_back(b, -(v + 1));
            }
        }
        std::sort(ends.begin(), ends.end());
        double majorant = 0.0;
        int inside = 0;
        for (size_t i = 0; i + 1 < ends.size(); ++i) {
            const int v = std::abs(ends[i].second) - 1;
            inside += ends[i].second > 0 ? 1 : -1;
            majorant = inside == 0 ? 0.0 : majorant + (ends[i].second > 0 ? 1.0 : -1.0) * bounds.volume_majorant[size_t(v)];
            const float t = ends[i].first, t_end = ends[i + 1].first;
            if (t_end > t && majorant > 0.0 && !visit(Segment{-1, glm::ivec3(0), x, w, t, t_end, float(majorant), 0.0f})) return;
        }
    }

    // Steps through the tentative collisions at `rate` in a segment's [t, t_end), calling at(t,
    // opaque) for each until it returns false; returns whether the segment's end was reached.
    // `opaque`: the segment is taken as opaque at t (nextCollision says why), with no collision
    // there, and `at` must stop the walk.
    template <class At>
    bool collisions(float t, float t_end, float rate, ReferenceRng& rng, int& events, At&& at) const {
        for (int here = 0;; ++here) {
            const std::optional<float> next = nextCollision(t, rate, here, rng);
            if (next && *next >= t_end) return true;
            if (next) {
                t = *next;
                ++events;
            }
            if (!at(t, !next)) return false;
        }
    }

    // Residual ratio tracking (Novak et al. 2014): in each brick segment the minorant c's share of
    // the optical depth is exact, exp(-c * length), and only the residual sigma - c is tracked, with
    // tentative collisions at rate m - c, each weighing 1 - (sigma - c) / (m - c). A brick of
    // uniform density that does not emit (emission raises its majorant) costs no event and adds no
    // noise (a dense cloud's core); where c is 0 it is plain ratio tracking. Of link set `link`'s
    // lights, only the volumes that shadow them count (their majorants still bound it).
    float transmittance(glm::vec3 x, glm::vec3 w, float dist, ReferenceRng& rng, int& events, int link = VX_ALL_LINKS) const {
        float T = 1.0f;
        walk(x, w, dist, [&](const Segment& s) {
            const float c = s.minorant, residual = s.majorant - c;
            if (s.t_end > s.t) T *= std::exp(-c * (s.t_end - s.t));
            if (T <= 0.0f) return false;
            if (!(residual > 0.0f)) return true;  // uniform here: exact
            return collisions(s.t, s.t_end, residual, rng, events, [&](float t, bool opaque) {
                T = opaque ? 0.0f : T * std::max(0.0f, 1.0f - (extinction(medium(s, t, true, link)) - c) / residual);
                return T > 0.0f;
            });
        });
        return T;
    }

    struct Flight {
        bool collided = false;
        float t = 0.0f;
        Collision cell{};
        glm::vec3 emitted{0.0f};  // emission collected up to the collision or the exit
    };

    // Delta tracking to the first real collision. Emission is estimated at every tentative
    // collision (Le / majorant each): the integral of transmittance times Le along the flight.
    Flight flight(glm::vec3 x, glm::vec3 w, ReferenceRng& rng, int& events) const {
        Flight f;
        const bool emits = k.P.emission_sources > 0;
        walk(x, w, 1e30f, [&](const Segment& s) {
            const float m = s.majorant;
            return collisions(s.t, s.t_end, m, rng, events, [&](float at, bool opaque) {
                const Collision c = medium(s, at);
                if (!opaque) {  // else the flight ends here
                    if (emits) f.emitted += emission(c) / m;
                    if (rng.next() * m >= extinction(c)) return true;  // a null collision
                }
                f.collided = true;
                f.t = at;
                f.cell = scattering(s, at, c);
                return false;
            });
        });
        return f;
    }

    // A flight by ratio tracking at the full majorant m to the end of the volume, for the camera ray
    // and for a path's last flight. Its tentative collisions are a Poisson process of rate m, so by
    // Campbell's theorem the sum over them of T(t) f(t) / m, with T(t) the running ratio-tracking
    // product, estimates the integral of T f along the ray without bias. With f = sigma that is the
    // probability of scattering at all: for the camera's flight (`camera`), one collision is chosen in proportion to its
    // term, by the pixel's stratified number, and the path scatters there with the whole sum as its
    // weight, where delta tracking would escape with probability T and give nothing. With f = Le it
    // is the emission along the ray. The product at the end is the transmittance to the outside
    // (the camera's alpha; the share of the ambient light a last flight brings, where delta
    // tracking brings all or nothing). The same events serve all three. Once T is below
    // kRouletteT, Russian roulette ends the flight or raises T back to it: a ray into a dense
    // medium does not walk to its far side for terms of under 2% (this saved 5-14% of a sample's
    // time on the study scenes).
    struct RatioFlight {
        Flight scatter;  // the chosen collision; collided is false when no term was positive
        float weight = 0.0f;  // the sum of T sigma / m: the path's throughput at the collision
        float transmittance = 1.0f;
        glm::vec3 emitted{0.0f};
    };

    static constexpr float kRouletteT = 0.02f;

    // A tentative collision that may be chosen: the running sum of the terms up to it.
    struct Candidate {
        float cumulative;
        float t;
        Segment segment;
    };

    // `camera`: the camera ray's flight (the flight chooses its scattering then). The flight ends
    // at t_max (a holdout's surface) if the volume does not end first.
    RatioFlight ratioFlight(glm::vec3 x, glm::vec3 w, bool camera, ReferenceRng& rng, int& events, float t_max = 1e30f) const {
        thread_local std::vector<Candidate> candidates;
        candidates.clear();
        RatioFlight p;
        float& T = p.transmittance;
        const bool emits = k.P.emission_sources > 0;
        walk(x, w, t_max, [&](const Segment& s) {
            const float m = s.majorant;
            return collisions(s.t, s.t_end, m, rng, events, [&](float at, bool opaque) {
                // A segment taken as opaque (nextCollision): all of T scatters here. The camera's
                // flight meets what the camera sees, and scatters only off the visible volumes.
                const Collision c = medium(s, at);
                const float sigma = opaque ? m : camera ? cameraExtinction(c) : extinction(c);
                const float scattering = opaque ? m : camera ? visibleExtinction(c) : sigma;
                const float term = opaque ? T : T * std::min(1.0f, scattering / m);
                if (emits && !opaque) p.emitted += T * emission(c) / m;
                if (term > 0.0f) {
                    p.weight += term;
                    if (camera) candidates.push_back({p.weight, at, s});
                }
                T = opaque ? 0.0f : T * std::max(0.0f, 1.0f - sigma / m);
                if (T < kRouletteT) T = rng.next() * kRouletteT < T ? kRouletteT : 0.0f;
                return T > 0.0f;
            });
        });
        if (candidates.empty()) return p;
        const float target = rng.stratified(ReferenceRng::kCameraScatter) * p.weight;
        const auto chosen = std::min(std::upper_bound(candidates.begin(), candidates.end(), target,
                                                      [](float v, const Candidate& c) { return v < c.cumulative; }),
                                     candidates.end() - 1);
        p.scatter = {true, chosen->t, scattering(chosen->segment, chosen->t, medium(chosen->segment, chosen->t)), glm::vec3(0.0f)};
        return p;
    }
};

// A sum of radiance as float, at most the float maximum (the sum is never NaN: its terms are >= 0).
float toFloat(double v) { return float(std::min(v, double(std::numeric_limits<float>::max()))); }
glm::vec3 toFloat(const glm::dvec3& v) { return {toFloat(v.x), toFloat(v.y), toFloat(v.z)}; }

// One path's contributions. With light groups, `layers` (the caller's, zeroed: one per group, then
// the emitted light's) receives the same terms as the light AOVs, each under the group of the
// light it came from; null without them.
struct PathSample {
    glm::vec3 direct{0.0f}, indirect{0.0f}, ambient{0.0f}, emission{0.0f};
    float transmittance = 1.0f;
    float scatter_weight = 0.0f;  // the camera pass's probability-of-scattering estimate
    float depth = 0.0f;           // camera-space distance of the first scattering
    int events = 0;
    glm::vec3* layers = nullptr;
    size_t layer_count = 0;

    // Light of an environment or the other lights scattered at the path's first scattering (direct)
    // or a later one, into `group`'s layer too.
    void addScattered(bool first, glm::vec3 light, int group) {
        (first ? direct : indirect) += light;
        if (layers) layers[size_t(group)] += light;
    }
    // What a path leaving along w with weight `beta` and transmittance T brings: ambient light, per
    // group; and each environment's radiance from w, weighted by multiple importance sampling
    // (power heuristic) against the map's own sampling at next-event estimation: w was drawn from
    // the phase function, with density `phase_pdf`. After the first scattering it is direct light.
    void addEscaped(const KernelInputs& in, glm::vec3 beta, float T, glm::vec3 w, float phase_pdf, bool first) {
        ambient += beta * in.params.ambient * T;
        if (layers)
            for (size_t g = 0; g < in.group_ambient.size(); ++g) layers[g] += beta * in.group_ambient[g] * T;
        for (const KernelInputs::Environment& env : in.environments) {
            const glm::vec3 radiance = env.map->lookup(w);
            if (!(radiance.x + radiance.y + radiance.z > 0.0f)) continue;
            const float light_pdf = env.map->pdf(w);
            const float mis = phase_pdf * phase_pdf / (phase_pdf * phase_pdf + light_pdf * light_pdf);
            addScattered(first, beta * radiance * (T * mis), env.group);
        }
    }
    // Emitted light reaching the camera (seen, or scattered: `to` is emission or indirect).
    void addEmitted(glm::vec3& to, glm::vec3 light) {
        to += light;
        if (layers) layers[layer_count - 1] += light;
    }
};

// The camera ray stops at t_cut (a holdout); the paths it starts are not held out.
PathSample tracePath(const Tracker& tr, const ReferenceSettings& rs, const KernelInputs& in,
                     std::vector<glm::vec3>& layers, glm::vec3 origin, glm::vec3 dir, glm::vec3 forward, float t_cut, ReferenceRng& rng) {
    CpuKernelData& k = tr.k;
    PathSample ps;
    std::fill(layers.begin(), layers.end(), glm::vec3(0.0f));
    if (!layers.empty()) {
        ps.layers = layers.data();
        ps.layer_count = layers.size();
    }
    const Tracker::RatioFlight camera = tr.ratioFlight(origin, dir, true, rng, ps.events, t_cut);
    ps.transmittance = camera.transmittance;
    ps.addEmitted(ps.emission, camera.emitted);
    if (!camera.scatter.collided) return ps;
    ps.scatter_weight = camera.weight;
    ps.depth = camera.scatter.t * glm::dot(dir, forward);
    if (rs.max_bounces == 0) return ps;
    const bool escapes_count = k.P.has_ambient != 0 || k.P.emission_sources > 0 || !in.environments.empty();
    glm::vec3 beta(camera.weight), x = origin + dir * camera.scatter.t, w = dir;
    Tracker::Collision cell = camera.scatter.cell;
    // The camera ray chose its collision among the visible extinction: its albedo is theirs.
    float cell_sigma = tr.visibleExtinction(cell);
    // Each turn scatters at x: next-event estimation to the lights, then a flight by delta tracking
    // (by ratio tracking when it is the last the path may take).
    for (int bounce = 0;; ++bounce) {
        const glm::vec3 arriving = beta;
        beta *= tr.albedo(cell, cell_sigma);
        const float g = tr.anisotropy(cell);
        for (int i = 0; i < k.P.light_count; ++i) {
            glm::vec3 wi;
            float dist;
            const kernel::VxLight light = k.vx_light(i);
            const glm::vec3 e = k.vx_light_incident(light, x, wi, dist);
            if (e.x + e.y + e.z <= 0.0f) continue;
            // A linked light is scattered by the volumes it lights (their share of the collision's
            // extinction) and shadowed by those it names; the path goes on through every volume.
            const int link = k.P.link_sets > 0 ? light.link_set : VX_ALL_LINKS;
            glm::vec3 weight = beta;
            float g_light = g;
            if (link != VX_ALL_LINKS) {
                const CpuKernelData::VxMedium m = tr.linked(x, link);
                weight = arriving * k.vx_medium_albedo(m, cell_sigma);
                g_light = k.vx_medium_g(m);
            }
            const float T = tr.transmittance(x, wi, dist, rng, ps.events, link);
            const glm::vec3 scattered = weight * e * (T * k.vx_phase_hg(glm::dot(wi, w), g_light));
            ps.addScattered(bounce == 0, scattered, light.group);
        }
        // Each environment by its map's importance, weighted against the phase function's
        // sampling of the same direction (addEscaped); an environment lights every volume.
        for (const KernelInputs::Environment& env : in.environments) {
            float light_pdf = 0.0f;
            const glm::vec3 wi = env.map->sample(glm::vec2(rng.next(), rng.next()), light_pdf);
            if (!(light_pdf > 0.0f)) continue;
            const float phase = k.vx_phase_hg(glm::dot(wi, w), g);
            const float mis = light_pdf * light_pdf / (light_pdf * light_pdf + phase * phase);
            const float T = tr.transmittance(x, wi, 1e30f, rng, ps.events);
            ps.addScattered(bounce == 0, beta * env.map->lookup(wi) * (T * phase * mis / light_pdf), env.group);
        }
        // After the last scattering only escaping light (ambient) or emission can still arrive.
        if (bounce + 1 == rs.max_bounces && !escapes_count) break;
        if (bounce + 1 >= rs.roulette_depth) {
            const float q = std::max({beta.x, beta.y, beta.z});
            if (q < 1.0f) {
                if (rng.next() >= q) break;
                beta /= q;
            }
        }
        if (beta.x + beta.y + beta.z <= 0.0f) break;
        const bool first = bounce == 0;
        const float u1 = first ? rng.stratified(ReferenceRng::kFirstDirectionU) : rng.next();
        const float u2 = first ? rng.stratified(ReferenceRng::kFirstDirectionV) : rng.next();
        const glm::vec3 before = w;
        w = k.vx_sample_hg(w, g, u1, u2);
        const float phase_pdf = k.vx_phase_hg(glm::dot(w, before), g);
        // The last flight brings only ambient light and emission: their expected values along w,
        // by residual ratio tracking where nothing emits.
        if (bounce + 1 == rs.max_bounces) {
            if (k.P.emission_sources > 0) {
                const Tracker::RatioFlight last = tr.ratioFlight(x, w, false, rng, ps.events);
                ps.addEmitted(ps.indirect, beta * last.emitted);
                ps.addEscaped(in, beta, last.transmittance, w, phase_pdf, first);
            } else {
                ps.addEscaped(in, beta, tr.transmittance(x, w, 1e30f, rng, ps.events), w, phase_pdf, first);
            }
            break;
        }
        const Tracker::Flight f = tr.flight(x, w, rng, ps.events);
        ps.addEmitted(ps.indirect, beta * f.emitted);
        if (!f.collided) {
            ps.addEscaped(in, beta, 1.0f, w, phase_pdf, first);
            break;
        }
        x += w * f.t;
        cell = f.cell;
        cell_sigma = tr.extinction(cell);
    }
    return ps;
}

}  // namespace

ExtinctionBounds brickExtinctionBounds(const KernelInputs& in) {
    CpuKernelData k = bindKernelData(in);
    const BrickAtlas& atlas = *in.atlas;
    const size_t slots = atlas.slots();
    const bool tf = k.P.use_transfer != 0;
    const float floor_emitting = 1.0f / voxelEdge(in.index_to_world);
    ExtinctionBounds b{std::vector<float>(slots, 0.0f), std::vector<float>(slots, 0.0f), {}};
    if (k.P.volume_count > 0) {
        // Several volumes: each volume's largest extinction (either filter stays within its
        // voxels' range), over the slots of its pages, or under a transfer function its table's
        // largest; where a volume emits, at least the one volume's floor, so that its emission is
        // sampled where it has no extinction.
        for (const kernel::VxVolume& v : in.volumes) {
            float hi = 0.0f;
            for (int e = v.pages.first; e < v.pages.first + v.pages.capacity; ++e)
                if (const int slot = in.pages->entries[size_t(e)].w; slot != VX_PAGE_EMPTY) hi = std::max(hi, atlas.density_range[size_t(slot)].y);
            if (v.transfer_row >= 0)
                hi = std::max_element(in.tf_lut.begin() + v.transfer_row, in.tf_lut.begin() + v.transfer_row + VX_TF_LUT_SIZE,
                                      [](const glm::vec4& a, const glm::vec4& b) { return a.w < b.w; })->w;
            const bool emits = k.P.emission_sources > 0 && v.emission_count > 0 && v.role == VX_ROLE_VISIBLE && !isEmptyRange(v.pages);
            b.volume_majorant.push_back(std::max(hi * v.density_scale, emits ? 1.0f / voxelEdge(glm::inverse(v.world_to_index)) : 0.0f));
        }
        return b;
    }
    // The slots a sample in slot s reads: s itself, under the B-spline its 26 neighbours (absent
    // ones read 0), and under motion blur every slot the medium can move from (atlas.motion_reach
    // bricks around; the velocity is only read in stored bricks). Past 2 bricks of reach, every
    // slot takes the bounds of all of them: (2 reach + 1)^3 lookups a slot would outweigh the
    // events a looser majorant adds.
    const int reach = (k.P.voxel_filter == VX_FILTER_TRICUBIC ? 1 : 0) + (k.P.use_velocity ? atlas.motion_reach : 0);
    const bool global = reach > 2;
    float global_lo = 0.0f, global_hi = 0.0f;   // absent bricks read 0
    bool global_emitting = false;
    for (size_t s = 0; global && s < slots; ++s) {
        global_hi = std::max(global_hi, atlas.density_range[s].y);
        global_lo = std::min(global_lo, atlas.density_range[s].x);
        for (int e = 0; e < k.P.emission_sources; ++e) global_emitting |= atlas.emission_max[size_t(e) * slots + s] > 0.0f;
    }
    for (size_t s = 0; s < slots; ++s) {
        // Filtered values stay within the range of the blocks they read (both filters are convex
        // combinations of voxels); the transfer function is linear between its table rows, so its
        // extremes over the range are at an end or at a row.
        float lo = global ? global_lo : atlas.density_range[s].x, hi = global ? global_hi : atlas.density_range[s].y;
        bool emitting = global_emitting;
        const int side = global ? 0 : 2 * reach + 1;
        for (int n = 0; n < side * side * side; ++n) {
            const glm::ivec3 offset(n % side - reach, n / side % side - reach, n / (side * side) - reach);
            const int read = k.vx_page_lookup(atlas.coords[s] + offset);
            if (read == VX_PAGE_EMPTY) {
                lo = std::min(lo, 0.0f);
                continue;
            }
            lo = std::min(lo, atlas.density_range[size_t(read)].x);
            hi = std::max(hi, atlas.density_range[size_t(read)].y);
            for (int e = 0; e < k.P.emission_sources; ++e) emitting |= atlas.emission_max[size_t(e) * slots + size_t(read)] > 0.0f;
        }
        float sigma_max = std::max(k.vx_value_extinction(lo), k.vx_value_extinction(hi));
        float sigma_min = std::min(k.vx_value_extinction(lo), k.vx_value_extinction(hi));
        for (int i = 0; tf && i < VX_TF_LUT_SIZE; ++i) {
            const float v = k.P.transfer_lo + float(i) / (float(VX_TF_LUT_SIZE - 1) * k.P.transfer_inv_range);
            if (v > lo && v < hi) {
                sigma_max = std::max(sigma_max, k.vx_value_extinction(v));
                sigma_min = std::min(sigma_min, k.vx_value_extinction(v));
            }
        }
        if (emitting) sigma_max = std::max(sigma_max, floor_emitting);
        b.majorant[s] = sigma_max;
        b.minorant[s] = std::max(0.0f, std::min(sigma_min, sigma_max));
    }
    return b;
}

float ratioTrackedTransmittance(const KernelInputs& in, const ExtinctionBounds& bounds, glm::vec3 x, glm::vec3 w,
                                float dist, ReferenceRng& rng) {
    CpuKernelData k = bindKernelData(in);
    int events = 0;
    std::atomic<uint64_t> opaque{0};
    return Tracker{k, bounds, opaque}.transmittance(x, w, dist, rng, events);
}

RenderImage renderReference(const KernelInputs& in, const ReferenceSettings& rs, uint64_t* opaque_segments,
                            ReferenceSums* sums, const std::vector<std::string>& light_groups) {
    CpuKernelData k = bindKernelData(in);
    if (k.P.surface_inv_range > 0.0f || k.P.noise_octaves > 0)
        throw InputError("render.method reference: effects.surface and effects.perturbation are march-only effects");
    const ExtinctionBounds bounds = brickExtinctionBounds(in);
    std::atomic<uint64_t> opaque{0};
    const Tracker tracker{k, bounds, opaque};
    RenderImage img;
    img.width = k.P.width;
    img.height = k.P.height;
    img.pixels.assign(size_t(img.width) * img.height, k.vx_empty_pixel());   // outside the region, empty
    const glm::ivec4 region = in.region;
    // With light groups, a layer per group and the emitted light's, summed per pixel as the AOVs are.
    const size_t layers = light_groups.empty() ? 0 : light_groups.size() + 1;
    const bool resume = sums && sums->width == img.width && sums->height == img.height && sums->samples < rs.spp &&
                        sums->layers.size() == img.pixels.size() * layers;
    if (sums && !resume)
        *sums = ReferenceSums{0, img.width, img.height, std::vector<ReferenceSums::Pixel>(img.pixels.size()),
                              std::vector<glm::dvec3>(img.pixels.size() * layers)};
    for (size_t l = 0; l < layers; ++l)
        img.light_groups.push_back({l < light_groups.size() ? light_groups[l] : kEmissionLayer, std::vector<glm::vec3>(img.pixels.size())});
    const int first = resume ? sums->samples : 0;
    const double n = rs.spp;
    ProgressTask progress("reference", int64_t(region.z - region.x) * (region.w - region.y) * (rs.spp - first), "samples");
    // Small tiles: a reference render is often a few pixels at many samples.
    tbb::parallel_for(tbb::blocked_range2d<int>(region.y, region.w, 4, region.x, region.z, 4), [&](const tbb::blocked_range2d<int>& r) {
        for (int y = r.rows().begin(); y < r.rows().end(); ++y)
            for (int x = r.cols().begin(); x < r.cols().end(); ++x) {
                const uint32_t pixel = uint32_t(y) * uint32_t(img.width) + uint32_t(x);
                glm::vec3 origin, dir, forward;
                k.vx_camera_ray(x, y, origin, dir, forward);
                const bool moving = k.P.motion_blur != 0, lens = k.P.lens_radius > 0.0f;
                // Sums in double, written clamped to the float maximum: HDR lights up to 3.4e38 are
                // legal, and a float sum of several such samples (or a luminance squared) overflows.
                ReferenceSums::Pixel local;
                ReferenceSums::Pixel& acc = sums ? sums->pixels[pixel] : local;
                std::vector<glm::dvec3> local_layers(sums ? 0 : layers);
                std::vector<glm::vec3> path_layers(layers);   // one path's, reused by each
                glm::dvec3* acc_layers = sums ? sums->layers.data() + size_t(pixel) * layers : local_layers.data();
                for (int s = first; s < rs.spp; ++s) {
                    ReferenceRng rng(uint32_t(rs.seed), pixel, uint32_t(s));
                    Tracker at_time = tracker;
                    if (moving) {   // a time within the shutter, stratified over the pixel's samples
                        const float fraction = rng.stratified(ReferenceRng::kShutterTime);
                        at_time.time = k.vx_shutter_time(fraction);
                        k.vx_camera_ray_at(x, y, fraction, origin, dir, forward);
                    }
                    glm::vec3 ray_origin = origin, ray_dir = dir;
                    if (lens)   // a point of the lens, stratified over the pixel's samples likewise
                        k.vx_through_lens(glm::vec2(rng.stratified(ReferenceRng::kLensU), rng.stratified(ReferenceRng::kLensV)), ray_origin,
                                          ray_dir, forward);
                    const float t_cut = k.vx_holdout_distance(x, y, ray_dir, forward);
                    const PathSample p = tracePath(at_time, rs, in, path_layers, ray_origin, ray_dir, forward, t_cut, rng);
                    for (size_t l = 0; l < layers; ++l) acc_layers[l] += path_layers[l];
                    acc.direct += p.direct;
                    acc.indirect += p.indirect;
                    acc.ambient += p.ambient;
                    acc.emission += p.emission;
                    acc.transmittance += p.transmittance;
                    acc.depth += double(p.depth) * p.scatter_weight;
                    acc.scatter_weight += p.scatter_weight;
                    acc.events += p.events;
                    // Luminance is linear: per term, so that no float sum overflows.
                    const double l = double(k.vx_luminance(p.direct)) + k.vx_luminance(p.indirect) +
                                     k.vx_luminance(p.ambient) + k.vx_luminance(p.emission);
                    acc.lum += l;
                    acc.lum2 += l * l;
                }
                kernel::VxPixel& px = img.pixels[pixel];
                px.direct = toFloat(acc.direct / n);
                px.indirect = toFloat(acc.indirect / n);
                px.ambient = toFloat(acc.ambient / n);
                px.emission = toFloat(acc.emission / n);
                px.transmittance = float(acc.transmittance / n);
                // With mattes, alpha is the visible volumes' coverage: the camera pass's probability
                // of scattering off them.
                const float alpha = k.P.volume_roles != 0 ? float(std::min(acc.scatter_weight / n, 1.0)) : 1.0f - px.transmittance;
                px.rgba = glm::vec4(toFloat((acc.direct + acc.indirect + acc.ambient + acc.emission) / n), alpha);
                for (size_t l = 0; l < layers; ++l) img.light_groups[l].rgb[pixel] = toFloat(acc_layers[l] / n);
                px.depth = acc.scatter_weight > 0.0 ? float(acc.depth / acc.scatter_weight) : 0.0f;
                px.samples = float(double(acc.events) / n);
                const double mean = acc.lum / rs.spp;
                px.variance = rs.spp > 1 ? toFloat(std::max(0.0, acc.lum2 - rs.spp * mean * mean) / (rs.spp - 1) / rs.spp) : 0.0f;
                progress.advance(rs.spp - first);
            }
    });
    if (sums) sums->samples = rs.spp;
    if (opaque_segments) *opaque_segments = opaque;
    return img;
}

}  // namespace voxlux
