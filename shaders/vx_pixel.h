// A pixel of the image: the camera rays through it (at the frame's time, or at a point of the
// shutter when the camera moves), its value before any ray met anything, and the running mean of
// its rays. The march (vx_march.h) fills it; the GL backend and the reference use these too.
#pragma once
#include "vx_types.h"

// The pixel's radiance so far: its four light AOVs summed.
VX_INLINE vec3 vx_pixel_radiance(VxPixel px) {
    return vx_radiance_add(vx_radiance_add(px.direct, px.ambient), vx_radiance_add(px.emission, px.indirect));
}

// A pixel no ray has met anything in: transparent and empty. The march starts from it, and a
// render region (render.region) leaves the pixels outside it so.
VX_INLINE VxPixel vx_empty_pixel() {
    VxPixel px;
    px.rgba = vec4(0.0f);
    px.direct = vec3(0.0f);
    px.ambient = vec3(0.0f);
    px.emission = vec3(0.0f);
    px.indirect = vec3(0.0f);
    px.transmittance = 1.0f;
    px.depth = 0.0f;
    px.samples = 0.0f;
    px.variance = 0.0f;
    return px;
}

// The ray of camera-to-world `m` through the centre of pixel (x, y); y = 0 is the top row.
void vx_camera_ray_of(mat4 m, int x, int y, VX_OUT(vec3) origin, VX_OUT(vec3) dir, VX_OUT(vec3) forward) {
    float w = float(P.width);
    float h = float(P.height);
    float sx = (2.0f * (float(x) + 0.5f) / w - 1.0f) * P.tan_half_fov * P.aspect;
    float sy = (1.0f - 2.0f * (float(y) + 0.5f) / h) * P.tan_half_fov;
    origin = vec3(m * vec4(0.0f, 0.0f, 0.0f, 1.0f));
    dir = normalize(vec3(m * vec4(sx, sy, -1.0f, 0.0f)));
    forward = normalize(vec3(m * vec4(0.0f, 0.0f, -1.0f, 0.0f)));
}

// The camera ray through pixel (x, y) at the frame's own time.
void vx_camera_ray(int x, int y, VX_OUT(vec3) origin, VX_OUT(vec3) dir, VX_OUT(vec3) forward) {
    vx_camera_ray_of(P.camera_to_world, x, y, origin, dir, forward);
}

// The same at `fraction` of the way from shutter open to close: where the camera moves, between
// its open and close rays (origins linearly, directions normalised linearly, which follows the
// rotation closely for the small turns of one shutter).
void vx_camera_ray_at(int x, int y, float fraction, VX_OUT(vec3) origin, VX_OUT(vec3) dir, VX_OUT(vec3) forward) {
    if (P.camera_moves == 0) {
        vx_camera_ray(x, y, origin, dir, forward);
        return;
    }
    vec3 o1;
    vec3 d1;
    vec3 f1;
    vx_camera_ray_of(P.camera_open, x, y, origin, dir, forward);
    vx_camera_ray_of(P.camera_close, x, y, o1, d1, f1);
    origin = mix(origin, o1, fraction);
    dir = normalize(mix(dir, d1, fraction));
    forward = normalize(mix(forward, f1, fraction));
}

// Depth of field (camera.fstop): the pinhole ray (origin, dir) through a thin lens of radius
// P.lens_radius sharp at camera-space depth P.focus_distance. The ray leaves the lens at the point
// `square` (in [0, 1)^2) maps to, uniformly over the disk, and passes where the pinhole ray meets
// the focal plane: a point there images to one point, a point at depth d to a disk of radius
// P.lens_radius |1/d - 1/P.focus_distance| in the image plane at unit distance. Camera-space
// depths (the holdouts', the depth AOV's) still count from the lens's plane.
void vx_through_lens(vec2 square, VX_INOUT(vec3) origin, VX_INOUT(vec3) dir, vec3 forward) {
    float r = P.lens_radius * sqrt(square.x);
    float phi = 6.2831853f * square.y;
    vec3 focus = origin + dir * (P.focus_distance / dot(dir, forward));
    // The lens's plane, across the ray's own forward (a camera moving within the shutter turns it).
    vec3 right = normalize(cross(forward, vec3(P.camera_to_world * vec4(0.0f, 1.0f, 0.0f, 0.0f))));
    vec3 up = cross(right, forward);
    origin = origin + (right * cos(phi) + up * sin(phi)) * r;
    dir = normalize(focus - origin);
}

// Depth holdouts (P.holdout): the distance along pixel (x, y)'s ray of unit direction dir to the
// CG surface, from its camera-space Z (over the cosine between the ray and the camera's forward
// axis); 1e30 where the pixel has none. The image's own pixel decides for every ray of the pixel.
float vx_holdout_distance(int x, int y, vec3 dir, vec3 forward) {
    if (P.holdout == 0) return 1e30f;
    float z = vx_holdout(y * P.width + x);
    return z < VX_FLOAT_MAX ? z / max(dot(dir, forward), 1e-6f) : 1e30f;
}

// The share of march sample k's segment [k dt, (k + 1) dt] in front of a holdout at distance
// t_cut: the sample's extinction and emission are scaled by it, so the optical depth a ray
// gathers ends at the surface exactly (for the march's piecewise-constant samples).
VX_INLINE float vx_cut_share(int k, float dt, float t_cut) { return clamp((t_cut - float(k) * dt) / dt, 0.0f, 1.0f); }

// Adds ray `px`, the n-th of a pixel's (n >= 2), to the mean `m` of the ones before: a running
// mean, which stays exactly the value of rays that all return the same. Depth is the opacity-
// weighted mean, as one ray weighs its samples (alpha_sum: the rays' alpha so far); the samples
// (the cost) add up.
void vx_pixel_mean_add(VX_INOUT(VxPixel) m, VxPixel px, int n, VX_INOUT(float) alpha_sum) {
    float w = 1.0f / float(n);
    m.rgba += (px.rgba - m.rgba) * w;
    m.direct += (px.direct - m.direct) * w;
    m.ambient += (px.ambient - m.ambient) * w;
    m.emission += (px.emission - m.emission) * w;
    m.indirect += (px.indirect - m.indirect) * w;
    m.transmittance += (px.transmittance - m.transmittance) * w;
    m.samples += px.samples;
    float alpha = px.rgba.w;
    if (alpha <= 0.0f) return;
    alpha_sum += alpha;
    m.depth = alpha_sum == alpha ? px.depth : m.depth + (px.depth - m.depth) * (alpha / alpha_sum);
}
