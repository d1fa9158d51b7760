// Deep samples along a camera ray, for deep EXR output (output.deep): the ray's stretches of
// medium, each a volumetric sample [z, z_back] with its premultiplied colour and its opacity, as
// OpenEXR's deep data and Nuke's deep compositing read them ("Interpreting OpenEXR Deep Pixels").
// A sample runs from transmittance T0 and radiance sum L0 (both from the camera) to T1 and L1:
// its alpha is 1 - T1 / T0 and its colour (L1 - L0) / T0, so compositing the samples front to
// back ("over") gives back exactly the flat pixel, sum of T0 * colour = L and 1 - T = alpha.
// The march opens a sample where the medium starts and closes it at an empty gap (the volume's
// depth structure) or once it holds its share of the optical depth the march can see,
// -ln(cutoff) / deep_samples. Past deep_samples, the two neighbours whose union is the most
// transparent merge ("over" again, so merging keeps colour and opacity exact). Cost: a few
// flops per sample of the march and one merge scan per sample past the limit; VX_DEEP_CAPACITY
// samples of storage per ray.
#pragma once
#include "vx_types.h"

// Samples a ray holds: output.deep_samples (at most 64) plus the one a merge makes room for. A
// GL program that writes no deep samples is compiled with 1, so its rays carry no such array.
#ifndef VX_DEEP_CAPACITY
#define VX_DEEP_CAPACITY 65
#endif

struct VxDeepRay {
    int count;              // closed samples in s
    bool open;              // a sample is being accumulated
    float z;                // the open sample's front and back (camera-space depth)
    float z_back;
    float T0;               // transmittance, radiance sum and optical depth at its front
    vec3 L0;
    float tau0;
    VxDeepSample s[VX_DEEP_CAPACITY];
};

VX_INLINE void vx_deep_begin(VX_INOUT(VxDeepRay) r) {
    r.count = 0;
    r.open = false;
}

// Optical depth of a closed sample (how much it hides), the merge's measure.
VX_INLINE float vx_deep_depth(VxDeepSample a) { return -log(max(1.0f - a.alpha, 1e-30f)); }

// a over b: a sample in front of another, as one.
VxDeepSample vx_deep_over(VxDeepSample a, VxDeepSample b) {
    VxDeepSample m;
    m.rgb = vx_radiance_add(a.rgb, b.rgb * (1.0f - a.alpha));
    m.alpha = 1.0f - (1.0f - a.alpha) * (1.0f - b.alpha);
    m.z = a.z;
    m.z_back = b.z_back;
    return m;
}

// Closes the open sample at transmittance T and radiance sum L; past the limit, merges the most
// transparent neighbouring pair.
void vx_deep_close(VX_INOUT(VxDeepRay) r, float T, vec3 L) {
    if (!r.open) return;
    r.open = false;
    VxDeepSample c;
    c.z = r.z;
    c.z_back = r.z_back;
    c.alpha = clamp(1.0f - T / r.T0, 0.0f, 1.0f);
    c.rgb = max(L - r.L0, vec3(0.0f)) / r.T0;
    VX_CHECK_INDEX(r.count, VX_DEEP_CAPACITY, "deep sample");
    r.s[r.count] = c;
    r.count += 1;
    if (r.count <= P.deep_samples) return;
    int best = 0;
    float best_depth = VX_FLOAT_MAX;
    for (int i = 0; i + 1 < r.count; ++i) {
        float depth = vx_deep_depth(r.s[i]) + vx_deep_depth(r.s[i + 1]);
        if (depth < best_depth) {
            best_depth = depth;
            best = i;
        }
    }
    r.s[best] = vx_deep_over(r.s[best], r.s[best + 1]);
    for (int i = best + 1; i + 1 < r.count; ++i) r.s[i] = r.s[i + 1];
    r.count -= 1;
}

// The march covered [z0, z1] of the ray starting at transmittance T0 (optical depth tau0) and
// radiance sum L0. A stretch that does not start where the open sample ends begins a new sample:
// what lies between was empty, so T0 and L0 also end the open one. The last sample is closed by
// vx_deep_close with the ray's final transmittance and radiance.
void vx_deep_span(VX_INOUT(VxDeepRay) r, float z0, float z1, float T0, vec3 L0, float tau0) {
    if (P.deep_samples <= 0) return;
    float share = -log(P.transmittance_cutoff) / float(P.deep_samples);
    if (r.open && (z0 > r.z_back * (1.0f + 1e-5f) || tau0 - r.tau0 >= share)) vx_deep_close(r, T0, L0);
    if (!r.open) {
        r.open = true;
        r.z = z0;
        r.T0 = max(T0, 1e-30f);
        r.L0 = L0;
        r.tau0 = tau0;
    }
    r.z_back = z1;
}
