// Extinction summed-area table queries (Schlegel et al. 2011): exact box sums, ambient occlusion
// from cuboid shells (Eq. 4, 5, 8) and shadow optical depth from a cone of cuboids (Eq. 7).
//
// The SAT holds integers, not floats: each light-grid cell is quantised to a multiple of the
// plane's quantum (a power of two chosen from the plane's maximum, src/summed_volume.cpp) and the
// prefix sums are kept modulo 2^96 in three 32-bit words. Box sums are differences of prefix sums,
// so they are exact in modular arithmetic whatever the prefix sums' size; the only rounding is the
// final conversion to float (< 3e-7 relative). docs/accuracy-sat.md derives the bound.
#pragma once
#include "vx_types.h"

// 96-bit unsigned integers as (low, middle, high) words, arithmetic modulo 2^96.
struct VxU96 {
    uint lo;
    uint mid;
    uint hi;
};

VX_INLINE VxU96 vx_u96_add(VxU96 a, VxU96 b) {
    uint c0;
    uint c1;
    uint c2;
    VxU96 r;
    r.lo = uaddCarry(a.lo, b.lo, c0);
    r.mid = uaddCarry(a.mid, b.mid, c1);
    r.mid = uaddCarry(r.mid, c0, c2);
    r.hi = a.hi + b.hi + c1 + c2;
    return r;
}

VX_INLINE VxU96 vx_u96_sub(VxU96 a, VxU96 b) {
    uint b0;
    uint b1;
    uint b2;
    VxU96 r;
    r.lo = usubBorrow(a.lo, b.lo, b0);
    r.mid = usubBorrow(a.mid, b.mid, b1);
    r.mid = usubBorrow(r.mid, b0, b2);
    r.hi = a.hi - b.hi - b1 - b2;
    return r;
}

// A non-negative sum below 2^96 as a float (three roundings).
VX_INLINE float vx_u96_float(VxU96 v) {
    return (float(v.hi) * 4294967296.0f + float(v.mid)) * 4294967296.0f + float(v.lo);
}

// SAT entry (x, y, z), 0 <= x <= dims.x etc., of plane `plane`. Entry (x, y, z) is the sum over
// cells [0, x) x [0, y) x [0, z); the x = 0, y = 0 and z = 0 faces are zero, so a box query needs
// no branches at the grid's low faces.
VX_INLINE VxU96 vx_sat_entry(int plane, int x, int y, int z) {
    int sx = S.dims.x + 1;
    int sy = S.dims.y + 1;
    int plane_entries = sx * sy * (S.dims.z + 1);
    int i = 3 * (plane * plane_entries + (z * sy + y) * sx + x);
    VxU96 v;
    v.lo = vx_sat_word(i);
    v.mid = vx_sat_word(i + 1);
    v.hi = vx_sat_word(i + 2);
    return v;
}

// Sum over the cells of box [lo, hi) (clamped to the grid; cells outside are empty), in the
// plane's value units: eight lookups, exact until the final float conversion.
float vx_sat_box(int plane, ivec3 lo, ivec3 hi) {
    ivec3 a = clamp(lo, ivec3(0), ivec3(S.dims));
    ivec3 b = clamp(hi, ivec3(0), ivec3(S.dims));
    if (a.x >= b.x || a.y >= b.y || a.z >= b.z) return 0.0f;
    VxU96 s = vx_sat_entry(plane, b.x, b.y, b.z);
    s = vx_u96_sub(s, vx_sat_entry(plane, a.x, b.y, b.z));
    s = vx_u96_sub(s, vx_sat_entry(plane, b.x, a.y, b.z));
    s = vx_u96_sub(s, vx_sat_entry(plane, b.x, b.y, a.z));
    s = vx_u96_add(s, vx_sat_entry(plane, a.x, a.y, b.z));
    s = vx_u96_add(s, vx_sat_entry(plane, a.x, b.y, a.z));
    s = vx_u96_add(s, vx_sat_entry(plane, b.x, a.y, a.z));
    s = vx_u96_sub(s, vx_sat_entry(plane, a.x, a.y, a.z));
    float q = plane == 0 ? S.quantum.x : plane == 1 ? S.quantum.y : plane == 2 ? S.quantum.z : S.quantum.w;
    return vx_u96_float(s) * q;
}

// Ambient-occlusion optical depth at cell `c` (Eq. 4, 8) from SAT plane `plane`:
//   tau = sum_i (SAT(Sh_i) - SAT(Sh_i-1)) * V_cell / (4 pi r_i^2),
// the 1/r^2-weighted extinction in cuboid shells Sh_i of inscribed radius r_i. The 1/(4 pi)
// makes tau the mean optical depth to the neighbourhood's edge: sigma * R in a homogeneous medium.
// Shell i = 1..n is the cube of 2k+1 cells centred on the cell (r = k + 1/2), k spread evenly out
// to the radius, the innermost being the cell itself, each at least one cell wider than the last.
float vx_ambient_tau(ivec3 c, int plane) {
    int n = int(S.shells.x);
    float sum = 0.0f;
    float inner = 0.0f;
    int k = -1;
    for (int i = 1; i <= n; ++i) {
        k = max(k + 1, int(floor(float(i) * S.shells.y / float(n))));
        float outer = vx_sat_box(plane, c - ivec3(k), c + ivec3(k + 1));
        float r = float(k) + 0.5f;
        sum += (outer - inner) / (r * r);
        inner = outer;
    }
    return sum * S.shells.z / (4.0f * VX_PI);
}

// Shadow optical depth at the centre of cell `c` towards light L (Eq. 7): the cone from the cell
// to the light is covered by cuboids stacked along its primary axis (the axis closest to the
// light direction, Fig. 7). Each cuboid contributes its mean extinction (the paper's weight
// h = 1 / V_q) times the length of ray inside it, so a thin cone in a homogeneous medium gives
// exactly sigma * distance. Cuboid boundaries on the primary axis lie on cell faces, spaced by
// the growth rate; across it they are rounded to cell faces and at least one cell wide.
float vx_cone_tau(ivec3 c, VxLight L) {
    vec3 p = vec3(c) + vec3(0.5f);
    vec3 w;
    bool directional = int(L.pos_type.w) == VX_LIGHT_DIRECTIONAL;
    if (directional) w = vec3(S.world_to_light * vec4(-vec3(L.dir_cos), 0.0f));
    else w = vec3(S.world_to_light * vec4(vec3(L.pos_type), 1.0f)) - p;
    vec3 aw = abs(w);
    int a = aw.x >= aw.y && aw.x >= aw.z ? 0 : (aw.y >= aw.z ? 1 : 2);
    if (aw[a] < 1e-20f) return 0.0f;     // the light is at this cell's centre
    vec3 wh = w / aw[a];                 // ray direction scaled to one cell per primary step
    bool forward = w[a] > 0.0f;
    // Primary-axis distance from the centre to the light, or to the grid's face when the light
    // is beyond it (outside the grid nothing attenuates).
    float to_face = forward ? float(S.dims[a] - c[a]) - 0.5f : float(c[a]) + 0.5f;
    float reach = directional ? to_face : min(aw[a], to_face);
    float step_world = length(vec3(S.light_to_world * vec4(wh, 0.0f)));

    // The cell's own half: its extinction over the distance to its face (or to the light).
    float tau = vx_sat_box(0, c, c + ivec3(1)) * min(0.5f, reach);
    float span = reach - 0.5f;
    int n = int(S.cone.y);
    float ratio = 1.0f + S.cone.z;
    float ratio_n = pow(ratio, float(n));
    float ratio_j = 1.0f;
    float t0 = 0.5f;
    for (int j = 1; j <= n && span > 0.0f; ++j) {
        // Fraction of the span covered after j cuboids: geometric in j (each cuboid 1 + growth
        // times longer than the one before), rounded to whole cells except at the light.
        ratio_j *= ratio;
        float f = S.cone.z > 1e-4f ? (ratio_j - 1.0f) / (ratio_n - 1.0f) : float(j) / float(n);
        float t1 = j == n ? reach : 0.5f + floor(f * span + 0.5f);
        if (t1 <= t0) continue;
        // Cross-section: the ray's extent over the segment widened by the cone radius at t1,
        // rounded to cell faces and at least one cell wide.
        float radius = S.cone.x * t1 * length(wh);
        vec3 e0 = p + wh * t0;
        vec3 e1 = p + wh * t1;
        ivec3 blo = ivec3(floor(min(e0, e1) - vec3(radius) + vec3(0.5f)));
        ivec3 bhi = max(ivec3(floor(max(e0, e1) + vec3(radius) + vec3(0.5f))), blo + ivec3(1));
        // Along the primary axis: the cells the segment [t0, t1) passes through.
        float pa0 = forward ? p[a] + t0 : p[a] - t1;
        float pa1 = forward ? p[a] + t1 : p[a] - t0;
        blo[a] = int(floor(pa0));
        bhi[a] = max(int(ceil(pa1)), blo[a] + 1);
        ivec3 size = bhi - blo;
        float volume = float(size.x) * float(size.y) * float(size.z);
        tau += vx_sat_box(0, blo, bhi) / volume * (t1 - t0);
        t0 = t1;
    }
    return tau * step_world;
}
