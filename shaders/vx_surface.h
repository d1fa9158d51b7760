// Kniss 2003's surface shading (Eq. 11): where the density's gradient is steep, a sample is lit
// in part as a surface, Blinn-Phong about the gradient's normal. Two central differences a
// sample (six density lookups), and only when P.surface_inv_range > 0.
#pragma once
#include "vx_sample.h"

// Kniss 2003 Eq. 11: how much of a sample is shaded as a surface (0 in homogeneous regions, 1
// where the density gradient is steep) and its normal, from central differences of the data.
struct VxSurface {
    vec3 normal;
    float weight;
};

VX_INLINE VxSurface vx_no_surface() {
    VxSurface s;
    s.normal = vec3(0.0f);
    s.weight = 0.0f;
    return s;
}

VxSurface vx_surface(vec3 p) {
    if (P.surface_inv_range <= 0.0f) return vx_no_surface();
    // One axis per iteration: a loop, so that a GLSL compiler inlines the density lookup (8 taps
    // under the tricubic filter) twice rather than six times.
    vec3 g = vec3(0.0f);
    for (int a = 0; a < 3; ++a) {
        vec3 e = vec3(a == 0 ? 1.0f : 0.0f, a == 1 ? 1.0f : 0.0f, a == 2 ? 1.0f : 0.0f);
        g += e * (vx_density_index(p + e) - vx_density_index(p - e));
    }
    g *= 0.5f;
    float m = length(g);
    float weight = clamp((m - P.surface_low) * P.surface_inv_range, 0.0f, 1.0f);
    // Index-space gradient to a world normal: the inverse transpose of index->world is world_to_index^T.
    VxSurface s;
    s.normal = m > 0.0f ? -normalize(transpose(mat3(P.world_to_index)) * g) : vec3(0.0f, 1.0f, 0.0f);
    s.weight = weight;
    return s;
}

// The factor Kniss Eq. 11 puts on the light from direction wi seen along dir: (1 - S) + S * f_s
// with f_s Blinn-Phong (diffuse plus specular) about the surface normal.
VX_INLINE float vx_surface_factor(VxSurface surface, vec3 wi, vec3 dir) {
    if (surface.weight <= 0.0f) return 1.0f;
    vec3 n = surface.normal;
    vec3 h = normalize(wi - dir);
    float fs = max(dot(n, wi), 0.0f) + P.specular * pow(max(dot(n, h), 0.0f), P.shininess);
    return (1.0f - surface.weight) + surface.weight * fs;
}
