// A ray's walk through the page table's bricks (Amanatides-Woo DDA at brick level), and the level
// above it that makes the walk's cost follow the bricks a ray meets rather than the bounding box:
// a region of VX_REGION_BRICKS^3 bricks that holds no brick is crossed in one step (one hashed
// lookup, at most 3 * VX_REGION_BRICKS additions) instead of a lookup and an unpredictable branch
// per brick, as NanoVDB's HDDA steps over empty nodes of its tree. The step lands on exactly the
// brick and plane crossings the brick walk would reach (the same float additions, in the same
// order), so skipping changes no sample. Also here: a ray clipped to the occupied bricks' box, and
// whether the walk visits a brick or may step over regions.
#pragma once
#include "vx_noise.h"
#include "vx_sample.h"

// Ray parameter t is world distance; the index-space point is o + t * d with d = W2I * world dir.
struct VxDda {
    ivec3 brick;
    ivec3 step;
    vec3 t_next;    // t at which the ray crosses the next brick plane on each axis
    vec3 t_delta;   // t between brick planes on each axis
    float t;        // t at which the ray entered the current brick
    float t_end;
};

float vx_safe_inv(float x) {
    return abs(x) > 1e-20f ? 1.0f / x : (x >= 0.0f ? 1e30f : -1e30f);
}

VxDda vx_dda_begin(vec3 o, vec3 d, float t0, float t1) {
    VxDda s;
    s.t = t0;
    s.t_end = t1;
    vec3 inv = vec3(vx_safe_inv(d.x), vx_safe_inv(d.y), vx_safe_inv(d.z));
    // Locate the first brick a hair inside the clipped segment so a start on a plane is stable.
    vec3 p = o + d * (t0 + 1e-5f * (t1 - t0));
    s.brick = ivec3(floor(p / float(VX_BRICK)));
    s.step = ivec3(d.x >= 0.0f ? 1 : -1, d.y >= 0.0f ? 1 : -1, d.z >= 0.0f ? 1 : -1);
    vec3 next_plane = vec3(s.brick + max(s.step, ivec3(0))) * float(VX_BRICK);
    s.t_next = (next_plane - o) * inv;
    s.t_delta = abs(inv) * float(VX_BRICK);
    return s;
}

float vx_dda_exit(VxDda s) {
    return min(s.t_end, min(s.t_next.x, min(s.t_next.y, s.t_next.z)));
}

// The axis whose plane the ray crosses first; on a tie the lower axis (x, then y).
VX_INLINE int vx_first_axis(vec3 t) {
    return t.x <= t.y && t.x <= t.z ? 0 : (t.y <= t.z ? 1 : 2);
}

// To the next brick: across the plane of vx_first_axis (written out, which the CPU runs faster).
void vx_dda_advance(VX_INOUT(VxDda) s) {
    s.t = vx_dda_exit(s);
    if (s.t_next.x <= s.t_next.y && s.t_next.x <= s.t_next.z) {
        s.brick.x += s.step.x;
        s.t_next.x += s.t_delta.x;
    } else if (s.t_next.y <= s.t_next.z) {
        s.brick.y += s.step.y;
        s.t_next.y += s.t_delta.y;
    } else {
        s.brick.z += s.step.z;
        s.t_next.z += s.t_delta.z;
    }
}

// Moves the walk out of region `r` (the one holding s.brick) to the first brick past it, in the
// state the brick walk would reach there: the brick walk crosses planes in order of (t, axis),
// each axis's planes at t_next, t_next + t_delta, ... summed one addition at a time.
void vx_dda_leave_region(VX_INOUT(VxDda) s, ivec3 r) {
    ivec3 steps;    // brick steps on each axis to its first plane outside the region
    vec3 leave;     // t of that plane
    for (int a = 0; a < 3; ++a) {
        int first = r[a] * VX_REGION_BRICKS;
        steps[a] = s.step[a] > 0 ? first + VX_REGION_BRICKS - s.brick[a] : s.brick[a] - first + 1;
        float t = s.t_next[a];
        for (int i = 1; i < steps[a]; ++i) t += s.t_delta[a];
        leave[a] = t;
    }
    int e = vx_first_axis(leave);
    float t_exit = leave[e];
    // The other axes cross the planes that come before (t_exit, e) and stay inside the region.
    for (int a = 0; a < 3; ++a) {
        if (a == e) continue;
        for (int i = 1; i < steps[a] && (s.t_next[a] < t_exit || (s.t_next[a] == t_exit && a < e)); ++i) {
            s.t_next[a] += s.t_delta[a];
            s.brick[a] += s.step[a];
        }
    }
    s.brick[e] += steps[e] * s.step[e];
    s.t_next[e] = t_exit + s.t_delta[e];
    s.t = min(s.t_end, t_exit);
}

// No region: where the region checks start (brick coordinates never reach it).
VX_INLINE ivec3 vx_no_region() { return ivec3(2147483647); }

// Leaves s.brick's region when it holds no brick, and says so. `region` is the last region found
// occupied (start with vx_no_region()): bricks inside it cost one comparison, not a lookup.
bool vx_dda_skip_empty_region(VX_INOUT(VxDda) s, VX_INOUT(ivec3) region) {
    ivec3 r = vx_region_of(s.brick);
    if (all(equal(r, region))) return false;
    if (vx_region_occupied(r)) {
        region = r;
        return false;
    }
    vx_dda_leave_region(s, r);
    return true;
}

// Past the empty regions from s.brick on, when `skips` (else nothing). Called after each step, so
// that the loop over bricks stays one plain loop.
void vx_dda_skip_empty(VX_INOUT(VxDda) s, VX_INOUT(ivec3) region, bool skips) {
    if (!skips) return;
    while (s.t < s.t_end && vx_dda_skip_empty_region(s, region)) {}
}

// The next brick, past empty regions.
void vx_dda_next(VX_INOUT(VxDda) s, VX_INOUT(ivec3) region, bool skips) {
    vx_dda_advance(s);
    vx_dda_skip_empty(s, region, skips);
}

// Clips [t0, t1] of the ray o + t * d against the index-space box [lo, hi]. Returns false when
// nothing is left.
bool vx_clip_to_box(vec3 o, vec3 d, vec3 lo, vec3 hi, VX_INOUT(float) t0, VX_INOUT(float) t1) {
    vec3 inv = vec3(vx_safe_inv(d.x), vx_safe_inv(d.y), vx_safe_inv(d.z));
    vec3 ta = (lo - o) * inv;
    vec3 tb = (hi - o) * inv;
    vec3 tmin = min(ta, tb);
    vec3 tmax = max(ta, tb);
    t0 = max(t0, max(tmin.x, max(tmin.y, tmin.z)));
    t1 = min(t1, min(tmax.x, min(tmax.y, tmax.z)));
    return t0 < t1;
}

// Clips [t0, t1] against the box of occupied bricks (grown by the perturbation's displacement,
// which can pull density outwards). Returns false when nothing is left.
bool vx_clip_to_bricks(vec3 o, vec3 d, VX_INOUT(float) t0, VX_INOUT(float) t1) {
    float grow = vx_displaced() ? P.displacement : 0.0f;
    vec3 lo = vec3(P.bricks_min) * float(VX_BRICK) - vec3(grow);
    vec3 hi = vec3(P.bricks_max + ivec3(1)) * float(VX_BRICK) + vec3(grow);
    return vx_clip_to_box(o, d, lo, hi, t0, t1);
}

// Index of the first sample t_k = (k + 0.5f) * dt with t_k >= t (inv_dt = 1 / dt). The same t
// ends one brick and starts the next, so every sample belongs to exactly one brick.
int vx_first_sample(float t, float inv_dt) {
    return max(int(ceil(t * inv_dt - 0.5f)), 0);
}

// Whether the march must visit a brick: occupied, or anywhere when displacement can pull
// density into empty bricks.
VX_INLINE bool vx_visits(int slot) { return slot != VX_PAGE_EMPTY || vx_displaced(); }

// Whether the march may step over regions that hold no brick: only when the page table has a
// regions' table (most regions of the box are empty), not when displacement can pull density into
// them, and not in GLSL. Mesa's llvmpipe (22.3, the only GL we can test on) mis-runs
// the region step: with it compiled in, some rays of a work group drop samples, even of scenes
// with no empty region (GlBackend.MatchesCpuWithTransferFunction), so GL keeps the brick walk.
VX_INLINE bool vx_skips_regions() {
#ifdef VX_GLSL
    return false;
#else
    return P.region_capacity > 0 && !vx_displaced();
#endif
}
