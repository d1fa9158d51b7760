// The illumination volume as the march reads it (propagation shadows): direct and indirect RGB
// radiance between cell centres, trilinear (8 cells) or, under L.propagation.light_filter
// tricubic, the cubic B-spline (64 cells). Trilinear has a kink at every cell centre, which shows
// as bands where a light cell spans several pixels and the light falls steeply across it (a dense
// medium); the spline is smooth (C2). The indirect block may be coarser (chroma subsampling,
// Ropinski 2010 Sec. 4.1). Accessor: vx_illum(index), one float array. The method's march hooks
// (cmake/kernel_contract.cmake) over L.propagation. Cost per sample and lookup (direct, then
// indirect): one cell transform and 24 reads (trilinear) or 192 (tricubic).
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
    if (L.propagation.light_filter == VX_FILTER_TRICUBIC) return vx_illum_spline(q, dims, offset);
    VxGridCell c = vx_grid_cell(q, dims, 3);
    c.base += offset;
    return vec3(VX_GRID_TRILINEAR(vx_illum, c, dims, 3, 0), VX_GRID_TRILINEAR(vx_illum, c, dims, 3, 1),
                VX_GRID_TRILINEAR(vx_illum, c, dims, 3, 2));
}

struct VxPropagationSample {
    vec3 x;   // the sample's world point: the hooks that read the volume transform it themselves,
              // so that a sample no hook reads costs nothing
};

VX_INLINE bool vx_propagation_varies() { return L.propagation.illum_dims.x > 0; }

// The volume holds the lights' shadowed light: the march lights every sample from it.
VX_INLINE bool vx_propagation_shadows() { return vx_propagation_varies(); }

VX_INLINE VxPropagationSample vx_propagation_sample(vec3 x) {
    VxPropagationSample s;
    s.x = x;
    return s;
}

// The first float of block `block`'s volume (vx_light_block: a light group's, of a link set).
VX_INLINE int vx_illum_block_first(int block) { return block * L.propagation.block_floats; }

// The sample's point in direct-light cells.
VX_INLINE vec3 vx_illum_point(VxPropagationSample s) { return vec3(L.propagation.world_to_illum * vec4(s.x, 1.0f)); }

// The illumination volume holds the lights' attenuated RGB together: each light keeps its phase,
// scaled per channel by the fraction of the lights' unshadowed radiance `unshadowed` that arrives.
// Exact for one light, and for any number when the phase is isotropic. Slightly negative values
// (float residue of subtracted lights) count as none.
VX_INLINE vec3 vx_propagation_direct(VxPropagationSample s, vec3 sum, vec3 unshadowed, int block) {
    if (!vx_propagation_varies()) return sum;
    vec3 arrived = max(vx_illum_at(vx_illum_point(s), L.propagation.illum_dims, vx_illum_block_first(block)), vec3(0.0f));
    return sum * vec3(unshadowed.x > 0.0f ? arrived.x / unshadowed.x : 0.0f, unshadowed.y > 0.0f ? arrived.y / unshadowed.y : 0.0f,
                      unshadowed.z > 0.0f ? arrived.z / unshadowed.z : 0.0f);
}

VX_INLINE bool vx_propagation_indirect_on() { return L.propagation.indirect_weight > 0.0f && vx_propagation_varies(); }

// Indirect radiance at a sample, weighted (0 when the scene has no indirect light or no volume).
VX_INLINE vec3 vx_propagation_indirect(VxPropagationSample s, int block) {
    if (!vx_propagation_indirect_on()) return vec3(0.0f);
    // Slightly negative values (float residue of subtracted lights) count as none.
    return max(vx_illum_at(vx_illum_point(s) / float(L.propagation.chroma_factor), L.propagation.chroma_dims,
                           vx_illum_block_first(block) + L.propagation.indirect_offset), vec3(0.0f)) *
           L.propagation.indirect_weight;
}
