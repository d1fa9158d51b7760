#include "reference/reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "core/progress.h"

#include "kernel/cpu_kernel.h"
#include "volume/brick_set.h"
#include "core/error.h"

namespace voxlux {
namespace {

using kernel::CpuKernel;

// PCG hash (Jarzynski and Olano 2020): one well-mixed 32-bit word per input word.
uint32_t pcgHash(uint32_t v) {
    const uint32_t state = v * 747796405u + 2891336453u;
    const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The tracker: the kernel bound to the inputs, and the majorants of its slots. Rays are in world
// units; the kernel's brick DDA walks them in index space with t as world distance.
struct Tracker {
    CpuKernel& k;
    const std::vector<float>& majorant;
    std::atomic<uint64_t>& opaque_segments;

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

    // Calls visit(slot, brick, o, d, t_begin, t_end, majorant) for each brick of non-zero majorant
    // the ray crosses within [0, t_max), in order, until visit returns false.
    template <class Visit>
    void walk(glm::vec3 x, glm::vec3 w, float t_max, Visit&& visit) const {
        const glm::vec3 o = k.vx_to_index_point(x), d = k.vx_to_index_dir(w);
        float t0 = 0.0f, t1 = t_max;
        if (!k.vx_clip_to_bricks(o, d, t0, t1)) return;
        CpuKernel::VxDda s = k.vx_dda_begin(o, d, t0, t1);
        while (s.t < s.t_end) {
            const int slot = k.vx_page_lookup(s.brick);
            if (slot != VX_PAGE_EMPTY && majorant[slot] > 0.0f &&
                !visit(slot, s.brick, o, d, s.t, k.vx_dda_exit(s), majorant[slot]))
                return;
            k.vx_dda_advance(s);
        }
    }

    // Ratio tracking: the product of (1 - sigma / majorant) over the tentative collisions.
    float transmittance(glm::vec3 x, glm::vec3 w, float dist, ReferenceRng& rng, int& events) const {
        float T = 1.0f;
        walk(x, w, dist, [&](int slot, glm::ivec3 brick, glm::vec3 o, glm::vec3 d, float t, float t_end, float m) {
            for (int here = 0;; ++here) {
                const std::optional<float> next = nextCollision(t, m, here, rng);
                if (!next) {
                    T = 0.0f;
                    return false;
                }
                t = *next;
                if (t >= t_end) return true;
                ++events;
                T *= std::max(0.0f, 1.0f - k.vx_extinction(k.vx_taps_at(slot, brick, o + d * t)) / m);
                if (T <= 0.0f) return false;
            }
        });
        return T;
    }

    struct Flight {
        bool collided = false;
        float t = 0.0f;
        CpuKernel::VxTaps cell{};
        glm::vec3 emitted{0.0f};  // emission collected up to the collision or the exit
    };

    // Delta tracking to the first real collision. Emission is estimated at every tentative
    // collision (Le / majorant each): the integral of transmittance times Le along the flight.
    Flight flight(glm::vec3 x, glm::vec3 w, ReferenceRng& rng, int& events) const {
        Flight f;
        const bool emits = k.P.emission_sources > 0;
        walk(x, w, 1e30f, [&](int slot, glm::ivec3 brick, glm::vec3 o, glm::vec3 d, float t, float t_end, float m) {
            for (int here = 0;; ++here) {
                const std::optional<float> next = nextCollision(t, m, here, rng);
                if (next && *next >= t_end) return true;
                if (next) {
                    t = *next;
                    ++events;
                }
                const CpuKernel::VxTaps c = k.vx_taps_at(slot, brick, o + d * t);
                if (!next) {  // opaque at float precision: the flight ends here
                    f.collided = true;
                    f.t = t;
                    f.cell = c;
                    return false;
                }
                if (emits) f.emitted += k.vx_emission(c) / m;
                if (rng.next() * m < k.vx_extinction(c)) {
                    f.collided = true;
                    f.t = t;
                    f.cell = c;
                    return false;
                }
            }
        });
        return f;
    }
};

// One path's contributions.
// A sum of radiance as float, at most the float maximum (the sum is never NaN: its terms are >= 0).
float toFloat(double v) { return float(std::min(v, double(std::numeric_limits<float>::max()))); }
glm::vec3 toFloat(const glm::dvec3& v) { return {toFloat(v.x), toFloat(v.y), toFloat(v.z)}; }

struct PathSample {
    glm::vec3 direct{0.0f}, indirect{0.0f}, ambient{0.0f}, emission{0.0f};
    float transmittance = 1.0f;
    float depth = 0.0f;  // camera-space distance of the first collision
    bool hit = false;
    int events = 0;
};

PathSample tracePath(const Tracker& tr, const ReferenceSettings& rs, glm::vec3 origin, glm::vec3 dir,
                     glm::vec3 forward, ReferenceRng& rng) {
    CpuKernel& k = tr.k;
    PathSample ps;
    ps.transmittance = tr.transmittance(origin, dir, 1e30f, rng, ps.events);
    const glm::vec3 ambient = k.P.ambient;
    const bool escapes_count = k.P.has_ambient != 0 || k.P.emission_sources > 0;
    const float g = k.P.anisotropy;
    glm::vec3 beta(1.0f), x = origin, w = dir;
    for (int bounce = 0;; ++bounce) {
        const Tracker::Flight f = tr.flight(x, w, rng, ps.events);
        (bounce == 0 ? ps.emission : ps.indirect) += beta * f.emitted;
        if (!f.collided) {
            if (bounce > 0) ps.ambient += beta * ambient;
            break;
        }
        if (bounce == 0) {
            ps.hit = true;
            ps.depth = f.t * glm::dot(dir, forward);
        }
        if (bounce == rs.max_bounces) break;
        x += w * f.t;
        beta *= k.vx_albedo(f.cell);
        for (int i = 0; i < k.P.light_count; ++i) {
            glm::vec3 wi;
            float dist;
            const glm::vec3 e = k.vx_light_incident(k.vx_light(i), x, wi, dist);
            if (e.x + e.y + e.z <= 0.0f) continue;
            const float T = tr.transmittance(x, wi, dist, rng, ps.events);
            (bounce == 0 ? ps.direct : ps.indirect) += beta * e * (T * k.vx_phase_hg(glm::dot(wi, w), g));
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
        const float u1 = rng.next(), u2 = rng.next();
        w = k.vx_sample_hg(w, g, u1, u2);
    }
    return ps;
}

}  // namespace

ReferenceRng::ReferenceRng(uint32_t seed, uint32_t pixel, uint32_t sample)
    : key_(pcgHash(seed ^ pcgHash(pixel ^ pcgHash(sample)))) {}

float ReferenceRng::next() { return float(pcgHash(key_ + pcgHash(dim_++)) >> 8) * 0x1p-24f; }

std::vector<float> brickMajorants(const KernelInputs& in) {
    CpuKernel k = bindCpuKernel(in);
    const BrickAtlas& atlas = *in.atlas;
    const size_t slots = atlas.slots();
    const bool tf = k.P.use_transfer != 0;
    const float floor_emitting = 1.0f / voxelEdge(atlas.index_to_world);
    std::vector<float> m(slots, 0.0f);
    // The slots a sample in slot s reads: s itself, and under the B-spline its 26 neighbours
    // (absent ones read 0).
    const bool tricubic = k.P.voxel_filter == VX_FILTER_TRICUBIC;
    for (size_t s = 0; s < slots; ++s) {
        // Filtered values stay within the range of the blocks they read (both filters are convex
        // combinations of voxels); the transfer function is linear between its table rows, so its
        // largest extinction over the range is at an end or at a row.
        float lo = atlas.density_range[s].x, hi = atlas.density_range[s].y;
        bool emitting = false;
        for (int n = tricubic ? 0 : 13; n < (tricubic ? 27 : 14); ++n) {
            const int read = k.vx_page_lookup(atlas.coords[s] + brickNeighbourOffset(n));
            if (read == VX_PAGE_EMPTY) {
                lo = std::min(lo, 0.0f);
                continue;
            }
            lo = std::min(lo, atlas.density_range[size_t(read)].x);
            hi = std::max(hi, atlas.density_range[size_t(read)].y);
            for (int e = 0; e < k.P.emission_sources; ++e) emitting |= atlas.emission_max[size_t(e) * slots + size_t(read)] > 0.0f;
        }
        float sigma = std::max(k.vx_value_extinction(lo), k.vx_value_extinction(hi));
        for (int i = 0; tf && i < VX_TF_LUT_SIZE; ++i) {
            const float v = k.P.transfer_lo + float(i) / (float(VX_TF_LUT_SIZE - 1) * k.P.transfer_inv_range);
            if (v > lo && v < hi) sigma = std::max(sigma, k.vx_value_extinction(v));
        }
        if (emitting) sigma = std::max(sigma, floor_emitting);
        m[s] = sigma;
    }
    return m;
}

float ratioTrackedTransmittance(const KernelInputs& in, const std::vector<float>& majorants, glm::vec3 x, glm::vec3 w,
                                float dist, ReferenceRng& rng) {
    CpuKernel k = bindCpuKernel(in);
    int events = 0;
    std::atomic<uint64_t> opaque{0};
    return Tracker{k, majorants, opaque}.transmittance(x, w, dist, rng, events);
}

RenderImage renderReference(const KernelInputs& in, const ReferenceSettings& rs, uint64_t* opaque_segments,
                            ReferenceSums* sums) {
    CpuKernel k = bindCpuKernel(in);
    if (k.P.surface_inv_range > 0.0f || k.P.noise_octaves > 0)
        throw InputError("render.method reference: effects.surface and effects.perturbation are march-only effects");
    const std::vector<float> majorants = brickMajorants(in);
    std::atomic<uint64_t> opaque{0};
    const Tracker tracker{k, majorants, opaque};
    RenderImage img;
    img.width = k.P.width;
    img.height = k.P.height;
    img.pixels.resize(size_t(img.width) * img.height);
    const bool resume = sums && sums->width == img.width && sums->height == img.height && sums->samples < rs.spp;
    if (sums && !resume) *sums = ReferenceSums{0, img.width, img.height, std::vector<ReferenceSums::Pixel>(img.pixels.size())};
    const int first = resume ? sums->samples : 0;
    const double n = rs.spp;
    ProgressTask progress("reference", int64_t(img.width) * img.height * (rs.spp - first), "samples");
    // Small tiles: a reference render is often a few pixels at many samples.
    tbb::parallel_for(tbb::blocked_range2d<int>(0, img.height, 4, 0, img.width, 4), [&](const tbb::blocked_range2d<int>& r) {
        for (int y = r.rows().begin(); y < r.rows().end(); ++y)
            for (int x = r.cols().begin(); x < r.cols().end(); ++x) {
                const uint32_t pixel = uint32_t(y) * uint32_t(img.width) + uint32_t(x);
                glm::vec3 origin, dir, forward;
                k.vx_camera_ray(x, y, origin, dir, forward);
                // Sums in double, written clamped to the float maximum: HDR lights up to 3.4e38 are
                // legal, and a float sum of several such samples (or a luminance squared) overflows.
                ReferenceSums::Pixel local;
                ReferenceSums::Pixel& acc = sums ? sums->pixels[pixel] : local;
                for (int s = first; s < rs.spp; ++s) {
                    ReferenceRng rng(uint32_t(rs.seed), pixel, uint32_t(s));
                    const PathSample p = tracePath(tracker, rs, origin, dir, forward, rng);
                    acc.direct += p.direct;
                    acc.indirect += p.indirect;
                    acc.ambient += p.ambient;
                    acc.emission += p.emission;
                    acc.transmittance += p.transmittance;
                    acc.depth += p.depth;
                    acc.events += p.events;
                    acc.hits += p.hit;
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
                px.rgba = glm::vec4(toFloat((acc.direct + acc.indirect + acc.ambient + acc.emission) / n), 1.0f - px.transmittance);
                px.depth = acc.hits ? float(acc.depth / acc.hits) : 0.0f;
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
