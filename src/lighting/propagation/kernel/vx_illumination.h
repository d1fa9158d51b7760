// The illumination volume as the march reads it (propagation shadows): direct and indirect RGB
// radiance, trilinear between cell centres; the indirect block may be coarser
// (chroma subsampling, Ropinski 2010 Sec. 4.1). Accessor: vx_illum(index), one float array.
#pragma once
#include "vx_grid.h"
#include "vx_optics.h"

// Direct radiance of all lights arriving at world point x through the medium.
vec3 vx_illum_direct(vec3 x) {
    VxGridCell c = vx_grid_cell(vec3(P.world_to_illum * vec4(x, 1.0f)), P.illum_dims, 3);
    return vec3(VX_GRID_TRILINEAR(vx_illum, c, P.illum_dims, 3, 0),
                VX_GRID_TRILINEAR(vx_illum, c, P.illum_dims, 3, 1),
                VX_GRID_TRILINEAR(vx_illum, c, P.illum_dims, 3, 2));
}

// Indirect radiance at x (0 when the scene has no indirect light or no illumination volume).
vec3 vx_illum_indirect(vec3 x) {
    if (P.indirect_weight <= 0.0f || P.illum_dims.x == 0) return vec3(0.0f);
    vec3 q = vec3(P.world_to_illum * vec4(x, 1.0f)) / float(P.chroma_factor);
    VxGridCell c = vx_grid_cell(q, P.chroma_dims, 3);
    c.base += P.indirect_offset;
    // Slightly negative values (float residue of subtracted lights) count as none.
    return max(vec3(VX_GRID_TRILINEAR(vx_illum, c, P.chroma_dims, 3, 0),
                    VX_GRID_TRILINEAR(vx_illum, c, P.chroma_dims, 3, 1),
                    VX_GRID_TRILINEAR(vx_illum, c, P.chroma_dims, 3, 2)),
               vec3(0.0f));
}
