// Procedural perturbation (Kniss 2003, Sec. III.D): multi-octave noise read from a small tiling
// table of random vec4s (src/optics/noise_table.cpp), evaluated in world space so the march and the
// light propagation perturb the same points. Component w perturbs extinction, xyz displace the
// data lookup (in index voxels) and tint the transport colour.
#pragma once
#include "vx_sample.h"

VX_INLINE bool vx_perturbed() { return P.noise_octaves > 0; }
VX_INLINE bool vx_displaced() { return P.noise_octaves > 0 && P.displacement > 0.0f; }

// The table at texel coordinates q (texel centres at integers), trilinear and wrapping.
VX_INLINE vec4 vx_noise_tile(vec3 q) {
    vec3 f = floor(q);
    vec3 t = q - f;
    int x0 = int(f.x) & (VX_NOISE_SIZE - 1);
    int y0 = int(f.y) & (VX_NOISE_SIZE - 1);
    int z0 = int(f.z) & (VX_NOISE_SIZE - 1);
    int x1 = (x0 + 1) & (VX_NOISE_SIZE - 1);
    int y1 = ((y0 + 1) & (VX_NOISE_SIZE - 1)) * VX_NOISE_SIZE;
    int z1 = ((z0 + 1) & (VX_NOISE_SIZE - 1)) * VX_NOISE_SIZE * VX_NOISE_SIZE;
    y0 *= VX_NOISE_SIZE;
    z0 *= VX_NOISE_SIZE * VX_NOISE_SIZE;
    return VX_TRILERP(vx_noise(z0 + y0 + x0), vx_noise(z0 + y0 + x1), vx_noise(z0 + y1 + x0), vx_noise(z0 + y1 + x1),
                      vx_noise(z1 + y0 + x0), vx_noise(z1 + y0 + x1), vx_noise(z1 + y1 + x0), vx_noise(z1 + y1 + x1),
                      t.x, t.y, t.z);
}

// Octaves of the table at world point x, each `lacunarity` times finer and `gain` times weaker,
// normalised by the sum of the weights so every component stays in [-1, 1].
vec4 vx_noise_fbm(vec3 x) {
    vec3 q = (x + P.noise_offset) * P.noise_frequency;
    vec4 sum = vec4(0.0f);
    float weight = 1.0f;
    float total = 0.0f;
    for (int o = 0; o < P.noise_octaves; ++o) {
        // Each octave is shifted by an irrational-looking offset so the tiles' seams do not line up.
        sum += weight * vx_noise_tile(q + vec3(float(o) * 7.31f, float(o) * 3.17f, float(o) * 5.53f));
        total += weight;
        weight *= P.gain;
        q *= P.lacunarity;
    }
    return sum / total;
}

// Extinction scaled by the noise at a point (never below 0).
VX_INLINE float vx_perturb_extinction(float sigma, vec4 n) {
    return sigma * max(1.0f + P.noise_density * n.w, 0.0f);
}

// Transport colour tinted by the noise, kept in (0, 1].
VX_INLINE vec3 vx_perturb_transport(vec3 t, vec4 n) {
    return clamp(t * (vec3(1.0f) + P.noise_transport * vec3(n)), vec3(1e-6f), vec3(1.0f));
}
