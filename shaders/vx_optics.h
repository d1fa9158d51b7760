// Optical properties at a sample (extinction, albedo, emission), light emission and phase.
#pragma once
#include "vx_sample.h"

// e^x for x <= 0, to about 2e-7 relative: x = n ln2 + r with |r| <= ln2 / 2, e^r by its Taylor
// series to r^6, 2^n built in the exponent bits. Written out (rather than the library's exp) so
// that the CPU build vectorises it inside the SIMD batches; the GPU runs the same arithmetic.
VX_INLINE float vx_exp(float x) {
    x = max(x, -87.0f);  // below this e^x is under the smallest normal float
    float n = floor(x * 1.44269504f + 0.5f);
    float r = (x - n * 0.693145752f) - n * 1.42860677e-6f;  // ln2 split in two: r keeps its low bits
    float p = 1.0f / 720.0f;
    p = p * r + 1.0f / 120.0f;
    p = p * r + 1.0f / 24.0f;
    p = p * r + 1.0f / 6.0f;
    p = p * r + 0.5f;
    p = p * r + 1.0f;
    p = p * r + 1.0f;
    return p * intBitsToFloat((int(n) + 127) << 23);
}

// (1 - e^-x) / x for x >= 0: the share of a constant source over a stretch of optical depth x
// that leaves it. Its series 1 - x/2 + x^2/6 below 1e-3, where the quotient loses its digits.
VX_INLINE float vx_exp_integral(float x) {
    return x < 1e-3f ? 1.0f - x * (0.5f - x * (1.0f / 6.0f)) : (1.0f - vx_exp(-x)) / x;
}

// Transfer-function lookup for a raw grid value in the table from row `first`, whose rows span
// grid values lo to lo + 1 / inv_range: rgb = albedo tint, a = extinction multiplier.
VX_INLINE vec4 vx_tf_eval_in(float value, int first, float lo, float inv_range) {
    float x = clamp((value - lo) * inv_range, 0.0f, 1.0f) * float(VX_TF_LUT_SIZE - 1);
    int i = first + min(int(x), VX_TF_LUT_SIZE - 2);
    return mix(vx_tf_lut(i), vx_tf_lut(i + 1), x - float(i - first));
}

// The same in the one volume's table.
VX_INLINE vec4 vx_tf_eval(float value) {
    return vx_tf_eval_in(value, 0, P.transfer_lo, P.transfer_inv_range);
}

// Extinction per world unit for a raw (reconstructed) grid value.
VX_INLINE float vx_value_extinction(float v) {
    if (P.use_transfer != 0) v = vx_tf_eval(v).w;
    return v * P.density_scale;
}

VX_INLINE float vx_extinction(VxTaps r) {
    return vx_value_extinction(vx_density_at(r));
}

// Albedo at a sample: the material's, tinted by the transfer function and the colour grid.
vec3 vx_albedo(VxTaps r) {
    vec3 a = P.albedo;
    if (P.use_transfer != 0) a *= vec3(vx_tf_eval(vx_density_at(r)));
    if (P.use_color_grid != 0) a *= vx_color_at(r);
    return a;
}

// Emitted radiance per world unit at a sample: each source's grid value through its own table
// (linear between rows, clamped to the grid's range), summed over the sources `first` to
// first + count - 1. The atlas holds the sources' channels one after another, `stride` floats
// apart, so a source's taps are the density's shifted (by `offset` to the first).
vec3 vx_emission_of(VxTaps r, int first, int count, int offset, int stride) {
    vec3 sum = vec3(0.0f);
    for (int s = 0; s < count; ++s) {
        VxTaps rs = vx_taps_offset(r, offset + s * stride);
        int source = first + s;
        float x = clamp(vx_emission_value_at(rs) * P.emission_domain[source], 0.0f, 1.0f) *
                  float(VX_EMISSION_LUT_SIZE - 1);
        int i = min(int(x), VX_EMISSION_LUT_SIZE - 2);
        int row = source * VX_EMISSION_LUT_SIZE + i;
        sum = vx_radiance_add(sum, vec3(mix(vx_emission_lut(row), vx_emission_lut(row + 1), x - float(i))));
    }
    return sum;
}

// The one volume's emission: all the scene's sources, right after one another.
VX_INLINE vec3 vx_emission(VxTaps r) {
    return vx_emission_of(r, 0, P.emission_sources, 0, P.emission_source_floats);
}

// Unshadowed radiance arriving at world point x from light L. Returns the direction towards the
// light in `wi` and the distance to it in `dist` (a huge value for directional lights).
// Point-light falloff is clamped at distance r_min so a light inside the medium stays finite.
vec3 vx_light_radiance(VxLight L, vec3 x, float r_min, VX_OUT(vec3) wi, VX_OUT(float) dist) {
    if (L.type == VX_LIGHT_DIRECTIONAL) {
        wi = -L.direction;
        dist = 1e30f;
        return L.color;
    }
    vec3 to_light = L.position - x;
    float d2 = dot(to_light, to_light);
    dist = sqrt(d2);
    wi = dist > 0.0f ? to_light / dist : vec3(0.0f, 1.0f, 0.0f);
    vec3 e = vx_radiance_add(vec3(0.0f), L.color / max(d2, r_min * r_min));   // a 3.4e38 light near x: inf * 0 is NaN
    if (L.type == VX_LIGHT_SPOT) {
        float cos_angle = dot(-wi, L.direction);
        e *= smoothstep(L.cos_outer, L.cos_inner, cos_angle);
    }
    return e;
}

// The march's version: the falloff clamps at half a march step.
vec3 vx_light_incident(VxLight L, vec3 x, VX_OUT(vec3) wi, VX_OUT(float) dist) {
    return vx_light_radiance(L, x, 0.5f * P.step, wi, dist);
}

// Rec. 709 luminance.
VX_INLINE float vx_luminance(vec3 c) { return dot(c, vec3(0.2126f, 0.7152f, 0.0722f)); }

// Henyey-Greenstein phase function; cos_theta is between the direction light travels and the
// direction it leaves towards the eye. 1 + g^2 - 2 g cos_theta is summed from two non-negative
// terms, so it stays at least (1 - |g|)^2 > 0 in float for every legal g (|g| < 1): written
// directly it cancels to 0 or below for g = 0.9999999 and the phase turned infinite.
VX_INLINE float vx_phase_hg(float cos_theta, float g) {
    cos_theta = clamp(cos_theta, -1.0f, 1.0f);   // a dot of unit vectors can round past 1
    float denom = g >= 0.0f ? (1.0f - g) * (1.0f - g) + 2.0f * g * (1.0f - cos_theta)
                            : (1.0f + g) * (1.0f + g) - 2.0f * g * (1.0f + cos_theta);
    return (1.0f - g) * (1.0f + g) / (4.0f * VX_PI * denom * sqrt(denom));
}

// A direction in which a path goes on after scattering, for one travelling along unit `dir`:
// its cosine with dir follows the Henyey-Greenstein phase (the inverse of its CDF; u1, u2 uniform
// in [0, 1)), so the phase cancels from the path's weight. Same convention as vx_phase_hg.
vec3 vx_sample_hg(vec3 dir, float g, float u1, float u2) {
    float cos_theta = 1.0f - 2.0f * u1;
    if (abs(g) > 1e-3f) {
        float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u1);
        cos_theta = clamp((1.0f + g * g - s * s) / (2.0f * g), -1.0f, 1.0f);
    }
    float sin_theta = sqrt(max(0.0f, 1.0f - cos_theta * cos_theta));
    float phi = 2.0f * VX_PI * u2;
    // Any orthonormal frame around dir (Duff et al. 2017).
    float flip = dir.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (flip + dir.z);
    float b = dir.x * dir.y * a;
    vec3 t1 = vec3(1.0f + flip * dir.x * dir.x * a, flip * b, -flip * dir.x);
    vec3 t2 = vec3(b, flip + dir.y * dir.y * a, -dir.y);
    return normalize(t1 * (sin_theta * cos(phi)) + t2 * (sin_theta * sin(phi)) + dir * cos_theta);
}
