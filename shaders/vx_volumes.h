// Several volumes in one scene (P.volume_count > 0): the medium where they overlap, and a ray's way
// through them. Each volume has its own placement, pages, material (a transfer function and a
// colour grid too) and role (VxVolume); all share the atlas. Overlap is physical: extinction adds; the albedo is the scattering-weighted mean of
// the volumes' (exactly the mixture's single-scattering albedo), and so is the Henyey-Greenstein g
// (the mixture's mean cosine, which one lobe of that g stands in for). Roles: every volume's
// extinction stops light; a camera ray meets the visible volumes and the mattes; only the visible
// ones scatter colour and emit (a matte or a shadow-only volume absorbs what it stops). Emission
// adds. Cost: per sample, a box test
// per volume and a hashed page lookup per volume whose box holds the sample; the space between
// the volumes' boxes is crossed in one jump per gap, not sample by sample.
#pragma once
#include "vx_dda.h"
#include "vx_motion.h"
#include "vx_optics.h"

// The volumes' medium at a point: the summed extinction (of every volume, as light meets it; of
// those a camera ray meets; of the visible ones), the visible ones' scattering (extinction times
// albedo), their scattering-weighted sum of g (weighted by the albedo's mean) and their summed
// emitted radiance per world unit.
struct VxMedium {
    vec3 scattering;
    float sigma;
    vec3 emitted;
    float sigma_camera;
    float sigma_visible;
    float g_sum;
    float g_weight;
    float pad0;
};

// The scattering-weighted albedo of extinction `sigma` (a light ray's, or a camera ray's), and the
// g of the medium's scattering.
VX_INLINE vec3 vx_medium_albedo(VxMedium m, float sigma) { return sigma > 0.0f ? m.scattering / sigma : vec3(0.0f); }
VX_INLINE float vx_medium_g(VxMedium m) { return m.g_weight > 0.0f ? m.g_sum / m.g_weight : 0.0f; }

// The box of volume V's bricks in its index space.
VX_INLINE vec3 vx_volume_lo(VxVolume V) { return vec3(V.pages.lo) * float(VX_BRICK); }
VX_INLINE vec3 vx_volume_hi(VxVolume V) { return vec3(V.pages.hi + ivec3(1)) * float(VX_BRICK); }

// The reconstruction of volume V at world point x at `time` (frames from the frame's own), in
// `taps`; false where no stored brick of it holds what is there. `inside` tells whether x lies in
// its box of bricks. A moving volume is read where its medium was (vx_motion.h): at x moved back
// by its velocity at x, which the joined atlas holds in its index voxels a second.
bool vx_volume_taps(VxVolume V, vec3 x, float time, VX_OUT(bool) inside, VX_OUT(VxTaps) taps) {
    vec3 p = vec3(V.world_to_index * vec4(x, 1.0f));
    ivec3 b = ivec3(floor(p / float(VX_BRICK)));
    inside = !(b.x < V.pages.lo.x || b.y < V.pages.lo.y || b.z < V.pages.lo.z || b.x > V.pages.hi.x || b.y > V.pages.hi.y ||
               b.z > V.pages.hi.z);
    if (!inside) return false;
    int slot = vx_table_find(b, V.pages.first, V.pages.capacity, V.pages.max_probe);
    if (slot == VX_PAGE_EMPTY) return false;
    taps = vx_taps_in(V.pages, slot, b, p);
    if (V.use_velocity == 0 || !vx_moving(time)) return true;
    vec3 q = p - vx_velocity_at(vx_taps_offset(taps, V.velocity_offset)) * (P.velocity_per_frame * time);
    bool found;
    taps = vx_taps_moved_to(V.pages, slot, b, q, found);
    return found;
}

// The extinction of volume V at its reconstruction `taps`, and in `tint` what its transfer
// function and (when `tinted`) its colour grid make of its albedo (as vx_extinction and vx_albedo
// do the one volume's).
float vx_volume_sigma(VxVolume V, VxTaps taps, bool tinted, VX_OUT(vec3) tint) {
    float value = vx_density_at(taps);
    tint = vec3(1.0f);
    if (V.transfer_row >= 0) {
        vec4 tf = vx_tf_eval_in(value, V.transfer_row, V.transfer_lo, V.transfer_inv_range);
        value = tf.w;
        tint = vec3(tf);
    }
    if (tinted && V.use_color != 0) tint *= vx_color_at(vx_taps_offset(taps, V.color_offset));
    return V.density_scale * value;
}

// The extinction of volume V at world point x at `time` (0 outside its stored bricks).
float vx_volume_extinction(VxVolume V, vec3 x, float time, VX_OUT(bool) inside) {
    VxTaps taps;
    vec3 tint;
    return vx_volume_taps(V, x, time, inside, taps) ? vx_volume_sigma(V, taps, false, tint) : 0.0f;
}

// The medium at world point x at `time`: its extinctions, and when `shading` (the camera's rays,
// the reference's flights; not shadow rays) its scattering, g and emission; `inside` tells whether
// x lies in any volume's box of bricks (when not, the ray may jump to vx_volumes_next_entry).
// For link set `link` (light linking; VX_ALL_LINKS: none), `sigma` is the extinction of the volumes
// that shadow its lights and the scattering and g those of the visible volumes its lights light;
// the camera's extinctions stay every volume's, and nothing emits.
VxMedium vx_volumes_medium(vec3 x, bool shading, float time, int link, VX_OUT(bool) inside) {
    VxMedium m;
    m.scattering = vec3(0.0f);
    m.sigma = 0.0f;
    m.emitted = vec3(0.0f);
    m.sigma_camera = 0.0f;
    m.sigma_visible = 0.0f;
    m.g_sum = 0.0f;
    m.g_weight = 0.0f;
    m.pad0 = 0.0f;
    inside = false;
    bool emission = shading && P.emission_sources > 0 && link == VX_ALL_LINKS;
    for (int v = 0; v < P.volume_count; ++v) {
        VxVolume V = vx_placed_volume(v);
        bool in_box;
        VxTaps taps;
        bool stored = vx_volume_taps(V, x, time, in_box, taps);
        inside = inside || in_box;
        if (!stored) continue;
        bool visible = V.role == VX_ROLE_VISIBLE;
        vec3 tint;
        float sigma = vx_volume_sigma(V, taps, shading && visible, tint);
        if (emission && visible && V.emission_count > 0)
            m.emitted = vx_radiance_add(m.emitted, vx_emission_of(taps, V.emission_first, V.emission_count, V.emission_offset, V.emission_stride));
        if (sigma <= 0.0f) continue;
        if (link == VX_ALL_LINKS || ((V.shadow_sets >> link) & 1) != 0) m.sigma += sigma;
        if (V.role == VX_ROLE_SHADOW_ONLY) continue;
        m.sigma_camera += sigma;
        if (!visible) continue;
        m.sigma_visible += sigma;
        if (!shading || (link != VX_ALL_LINKS && ((V.lit_sets >> link) & 1) == 0)) continue;
        vec3 albedo = V.albedo * tint;
        m.scattering += sigma * albedo;
        float weight = sigma * (albedo.x + albedo.y + albedo.z);
        m.g_sum += weight * V.anisotropy;
        m.g_weight += weight;
    }
    return m;
}

// The part [t0, t1] of the ray from world point x along unit direction w that crosses any
// volume's box (their hull along the ray); false when it crosses none.
bool vx_volumes_clip(vec3 x, vec3 w, VX_INOUT(float) t0, VX_INOUT(float) t1) {
    float lo = 1e30f;
    float hi = -1e30f;
    for (int v = 0; v < P.volume_count; ++v) {
        VxVolume V = vx_placed_volume(v);
        float a = t0;
        float b = t1;
        if (!vx_clip_to_box(vec3(V.world_to_index * vec4(x, 1.0f)), vec3(V.world_to_index * vec4(w, 0.0f)), vx_volume_lo(V),
                            vx_volume_hi(V), a, b))
            continue;
        lo = min(lo, a);
        hi = max(hi, b);
    }
    t0 = lo;
    t1 = hi;
    return t0 < t1;
}

// The first t in [t, t_end] at which the ray enters a volume's box; 1e30 when it enters none.
float vx_volumes_next_entry(vec3 x, vec3 w, float t, float t_end) {
    float next = 1e30f;
    for (int v = 0; v < P.volume_count; ++v) {
        VxVolume V = vx_placed_volume(v);
        float a = t;
        float b = t_end;
        if (vx_clip_to_box(vec3(V.world_to_index * vec4(x, 1.0f)), vec3(V.world_to_index * vec4(w, 0.0f)), vx_volume_lo(V),
                           vx_volume_hi(V), a, b))
            next = min(next, a);
    }
    return next;
}

// The sample after k to take on a ray at t_k = (k + 0.5) * dt that lies in no volume's box: the
// one before the next entry (the caller's loop steps to it), or -1 when the ray enters no box
// before t_end.
int vx_volumes_skip(vec3 x, vec3 w, int k, float dt, float t_end) {
    float next = vx_volumes_next_entry(x, w, (float(k) + 0.5f) * dt, t_end);
    if (next > t_end) return -1;
    return max(k, vx_first_sample(next, 1.0f / dt) - 1);
}

// The ray's sample t_k = (k + 0.5) * dt inside a volume's box, from k on: k moves past the space
// between boxes, and m is the medium there at `time` (shaded, and of link set `link`, as
// vx_volumes_medium says); false once the samples pass t_end.
bool vx_volumes_sample(vec3 x, vec3 w, float dt, float t_end, bool shading, float time, int link, VX_INOUT(int) k, VX_OUT(VxMedium) m) {
    for (;; ++k) {
        float t = (float(k) + 0.5f) * dt;
        if (t > t_end) return false;
        bool inside;
        m = vx_volumes_medium(x + w * t, shading, time, link, inside);
        if (inside) return true;
        k = vx_volumes_skip(x, w, k, dt, t_end);
        if (k < 0) return false;
    }
}

// Optical depth of the volumes (those that shadow link set `link`'s lights) from world point x
// along unit direction w over [0, dist], summed at samples t_k = (k + 0.5) * dt, in the medium at
// the frame's own time; it stops once past tau_cut.
float vx_volumes_optical_depth(vec3 x, vec3 w, float dist, float dt, float tau_cut, int link) {
    float t0 = 0.0f;
    float t1 = dist;
    if (!vx_volumes_clip(x, w, t0, t1)) return 0.0f;
    float tau = 0.0f;
    VxMedium m;
    for (int k = vx_first_sample(t0, 1.0f / dt); tau <= tau_cut && vx_volumes_sample(x, w, dt, t1, false, 0.0f, link, k, m); ++k) tau += m.sigma * dt;
    return tau;
}
