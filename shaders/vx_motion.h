// Velocity motion blur (render.motion_blur; docs/scene.md, "Motion blur"). Each camera ray takes a
// time within the shutter, stratified over a pixel's rays, and the medium is looked up where it was
// at that time: first-order Eulerian advection, as production renderers blur volume caches. What
// sits at x at time t (frames from the frame's own time) is what the frame holds at x - v(x) t, v
// the velocity grid in world units a frame. The camera moves from its open to its close transform.
// Cost: the march runs P.time_samples rays a pixel; a sample where the medium moves reads the
// velocity (one more reconstruction) and the moved point, with a page lookup when that lies in
// another brick.
#pragma once
#include "vx_pixel.h"
#include "vx_sample.h"

VX_DEFINE_RECONSTRUCT(vec3, vx_velocity_at, vx_atlas_velocity)

VX_INLINE bool vx_is_zero(vec3 v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; }

// Whether a ray at `time` looks the medium up elsewhere than the frame holds it.
VX_INLINE bool vx_moving(float time) { return P.use_velocity != 0 && time != 0.0f; }

// How far, in world units, the medium at index point p of stored brick (slot, b) has moved by
// `time`: 0 where no velocity is bound, at the frame's own time, and outside stored bricks.
VX_INLINE vec3 vx_motion_shift(int slot, ivec3 b, vec3 p, float time) {
    if (!vx_moving(time) || slot == VX_PAGE_EMPTY) return vec3(0.0f);
    return mat3(P.velocity_to_world) * vx_velocity_at(vx_taps_at(slot, b, p)) * (P.velocity_per_frame * time);
}

// The reconstruction at index point q among `pages`, where a point of stored brick (slot, b) was
// in the frame: its own brick's slot, or another's looked up. `found` is false where q lies in no
// stored brick (its values are all 0 there).
VX_INLINE VxTaps vx_taps_moved_to(VxPageRange pages, int slot, ivec3 b, vec3 q, VX_OUT(bool) found) {
    ivec3 qb = ivec3(floor(q / float(VX_BRICK)));
    int qs = all(equal(qb, b)) ? slot : vx_page_lookup_in(pages, qb);
    found = qs != VX_PAGE_EMPTY;
    return vx_taps_in(pages, found ? qs : slot, qb, q);    // not found: any stored cell, unused
}

// The reconstruction at index point p of the one volume's stored brick (slot, b) moved back by
// world `shift`: where the medium now at p was in the frame. Unmoved, it is vx_taps_at(slot, b, p)
// itself, so a still medium renders bit for bit as without blur.
VX_INLINE VxTaps vx_moved_taps(int slot, ivec3 b, vec3 p, vec3 shift, VX_OUT(bool) found) {
    found = true;
    if (vx_is_zero(shift)) return vx_taps_at(slot, b, p);
    return vx_taps_moved_to(vx_own_pages(), slot, b, p - vx_to_index_dir(shift), found);
}

// Where in [0, 1) pixel (x, y) shifts its rays' strata: one offset a pixel, so the copies of a
// moving edge that a pixel's few rays see turn into fine noise across pixels, not bands.
VX_INLINE float vx_pixel_time_offset(int x, int y) {
    return float(vx_hash(uint(x) * 1973u + vx_hash(uint(y) + 9277u)) >> 8) * (1.0f / 16777216.0f);
}

// Ray i of a pixel's n: its fraction of the way from shutter open to close, and its time in frames.
VX_INLINE float vx_shutter_fraction(int i, int n, float offset) { return (float(i) + offset) / float(n); }
VX_INLINE float vx_shutter_time(float fraction) { return P.shutter_open + (P.shutter_close - P.shutter_open) * fraction; }

// Where on the lens ray i of a pixel's n leaves, as a point of the unit square: the R2 sequence
// (Roberts 2018), whose first n points cover the square evenly for every n, shifted by an offset a
// pixel so that neighbours' rays differ.
VX_INLINE vec2 vx_lens_square(int i, int x, int y) {
    vec2 offset = vec2(float(vx_hash(uint(x) * 7919u + vx_hash(uint(y) + 104729u)) >> 8),
                       float(vx_hash(uint(y) * 6007u + vx_hash(uint(x) + 15485863u)) >> 8)) * (1.0f / 16777216.0f);
    return fract(vec2(0.7548776662f, 0.5698402910f) * float(i) + offset);
}

// Ray i of pixel (x, y)'s P.time_samples: its world origin, unit direction and the camera's
// forward, at the time it returns (frames from the frame's own; without motion blur, the one ray
// at the frame's time), through the lens where the camera has depth of field.
float vx_pixel_ray(int x, int y, int i, VX_OUT(vec3) origin, VX_OUT(vec3) dir, VX_OUT(vec3) forward) {
    float time = 0.0f;
    if (P.motion_blur == 0) {
        vx_camera_ray(x, y, origin, dir, forward);
    } else {
        float fraction = vx_shutter_fraction(i, P.time_samples, vx_pixel_time_offset(x, y));
        vx_camera_ray_at(x, y, fraction, origin, dir, forward);
        time = vx_shutter_time(fraction);
    }
    if (P.lens_radius > 0.0f) vx_through_lens(vx_lens_square(i, x, y), origin, dir, forward);
    return time;
}
