// Optical properties at a sample (material / transfer function), light emission and phase.
#pragma once
#include "vx_sample.h"

struct VxOptics {
    float sigma_t;   // extinction, per world unit
    vec3 albedo;     // single-scattering albedo
    vec3 emission;   // emitted radiance per world unit
};

// Transfer-function lookup for a raw grid value: rgb = albedo tint, a = extinction multiplier.
vec4 vx_tf_eval(float value) {
    float x = clamp((value - P.tf_domain.x) * P.tf_domain.y, 0.0f, 1.0f) * float(VX_TF_LUT_SIZE - 1);
    int i = min(int(x), VX_TF_LUT_SIZE - 2);
    return mix(vx_tf_lut(i), vx_tf_lut(i + 1), x - float(i));
}

float vx_extinction(VxCorners c) {
    float v = VX_TRILINEAR(vx_atlas_density, c);
    if (P.tf_domain.z > 0.5f) v = vx_tf_eval(v).w;
    return v * P.material.w;
}

VxOptics vx_optics(VxCorners c) {
    VxOptics o;
    float v = VX_TRILINEAR(vx_atlas_density, c);
    o.albedo = vec3(P.material);
    if (P.tf_domain.z > 0.5f) {
        vec4 tf = vx_tf_eval(v);
        v = tf.w;
        o.albedo *= vec3(tf);
    }
    o.sigma_t = v * P.material.w;
    if (P.tf_domain.w > 0.5f) o.albedo *= VX_TRILINEAR(vx_atlas_color, c);
    o.emission = vec3(0.0f);
    if (P.emission.w > 0.5f) o.emission = vec3(P.emission) * VX_TRILINEAR(vx_atlas_emission, c);
    return o;
}

// Unshadowed radiance arriving at world point x from light L. Returns the direction towards the
// light in `wi` and the distance to it in `dist` (a huge value for directional lights).
// Point-light falloff is clamped at half a march step so a light inside the medium stays finite.
vec3 vx_light_incident(VxLight L, vec3 x, VX_OUT(vec3) wi, VX_OUT(float) dist) {
    int type = int(L.pos_type.w);
    if (type == VX_LIGHT_DIRECTIONAL) {
        wi = -vec3(L.dir_cos);
        dist = 1e30f;
        return vec3(L.color);
    }
    vec3 to_light = vec3(L.pos_type) - x;
    float d2 = dot(to_light, to_light);
    dist = sqrt(d2);
    wi = dist > 0.0f ? to_light / dist : vec3(0.0f, 1.0f, 0.0f);
    float r_min = 0.5f * P.march.x;
    vec3 e = vec3(L.color) / max(d2, r_min * r_min);
    if (type == VX_LIGHT_SPOT) {
        float cos_angle = dot(-wi, vec3(L.dir_cos));
        e *= smoothstep(L.dir_cos.w, L.color.w, cos_angle);
    }
    return e;
}

// Henyey-Greenstein phase function; cos_theta is between the direction light travels and the
// direction it leaves towards the eye.
float vx_phase_hg(float cos_theta, float g) {
    float denom = 1.0f + g * g - 2.0f * g * cos_theta;
    return (1.0f - g * g) / (4.0f * VX_PI * denom * sqrt(denom));
}
