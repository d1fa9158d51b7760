// The illumination volume as the march reads it (propagation shadows): direct and indirect RGB
// radiance between cell centres, trilinear (8 cells) or, under P.light_filter tricubic, the cubic
// B-spline (64 cells). Trilinear has a kink at every cell centre, which shows as bands where a
// light cell spans several pixels and the light falls steeply across it (a dense medium); the
// spline is smooth (C2). The indirect block may be coarser (chroma subsampling, Ropinski 2010
// Sec. 4.1). Accessor: vx_illum(index), one float array.
#pragma once
#include "vx_grid.h"
#include "vx_optics.h"

// The RGB at float `at` of the illumination volume.
VX_INLINE vec3 vx_illum_rgb(int at) { return vec3(vx_illum(at), vx_illum(at + 1), vx_illum(at + 2)); }

// The cubic B-spline at grid point q of the block of `dims` cells that starts at float `offset`:
// the 4x4x4 cells around q, the edge cells repeated past the grid's faces (as the trilinear read
// clamps to the outer centres).
vec3 vx_illum_spline(vec3 q, ivec3 dims, int offset) {
    // Clamped first, so that the int conversions below stay defined for any q; a cell two past a
    // face reads the edge as well.
    vec3 g = clamp(q - vec3(0.5f), vec3(-2.0f), vec3(dims) + vec3(1.0f));
    vec3 first = floor(g);
    VxSplineWeights w = vx_spline_weights(g - first);
    vec4 wx = vec4(w.w0.x, w.w1.x, w.w2.x, w.w3.x);
    vec4 wy = vec4(w.w0.y, w.w1.y, w.w2.y, w.w3.y);
    vec4 wz = vec4(w.w0.z, w.w1.z, w.w2.z, w.w3.z);
    ivec3 lo = ivec3(first) - ivec3(1);
    ivec4 ox;
    ivec4 oy;
    ivec4 oz;
    for (int n = 0; n < 4; ++n) {
        ox[n] = 3 * clamp(lo.x + n, 0, dims.x - 1);
        oy[n] = 3 * dims.x * clamp(lo.y + n, 0, dims.y - 1);
        oz[n] = 3 * dims.x * dims.y * clamp(lo.z + n, 0, dims.z - 1);
    }
    // Each term is a weight product times a value, never more than the value: a sum over values
    // near the float maximum can round past it to inf (clamped below), but never meets inf * 0.
    vec3 sum = vec3(0.0f);
    for (int c = 0; c < 4; ++c)
        for (int b = 0; b < 4; ++b) {
            float wyz = wy[b] * wz[c];
            int row_at = offset + oy[b] + oz[c];
            for (int a = 0; a < 4; ++a) sum += (wyz * wx[a]) * vx_illum_rgb(row_at + ox[a]);
        }
    return vx_radiance_add(vec3(0.0f), sum);
}

// RGB at grid point q of the block of `dims` cells that starts at float `offset`.
vec3 vx_illum_at(vec3 q, ivec3 dims, int offset) {
    if (P.light_filter == VX_FILTER_TRICUBIC) return vx_illum_spline(q, dims, offset);
    VxGridCell c = vx_grid_cell(q, dims, 3);
    c.base += offset;
    return vec3(VX_GRID_TRILINEAR(vx_illum, c, dims, 3, 0), VX_GRID_TRILINEAR(vx_illum, c, dims, 3, 1),
                VX_GRID_TRILINEAR(vx_illum, c, dims, 3, 2));
}

// Direct radiance of all lights arriving at world point x through the medium.
vec3 vx_illum_direct(vec3 x) { return vx_illum_at(vec3(P.world_to_illum * vec4(x, 1.0f)), P.illum_dims, 0); }

// Indirect radiance at x (0 when the scene has no indirect light or no illumination volume).
vec3 vx_illum_indirect(vec3 x) {
    if (P.indirect_weight <= 0.0f || P.illum_dims.x == 0) return vec3(0.0f);
    vec3 q = vec3(P.world_to_illum * vec4(x, 1.0f)) / float(P.chroma_factor);
    // Slightly negative values (float residue of subtracted lights) count as none.
    return max(vx_illum_at(q, P.chroma_dims, P.indirect_offset), vec3(0.0f));
}
