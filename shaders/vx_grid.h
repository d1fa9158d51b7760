// Cell-centred grids of floats as the march reads them (the light cache, the illumination
// volume): where a point falls among the cell centres, and the trilinear value of a channel there.
#pragma once
#include "vx_sample.h"

// The trilinear cell of a sample in a grid: first float of its lowest corner and fractions.
struct VxGridCell {
    int base;
    float fx;
    float fy;
    float fz;
};

// The trilinear cell of grid point q (cell centres at i + 0.5) in a grid of `dims` cells holding
// `floats` values per cell: first float of its lowest corner and fractions, clamped to the centres.
VxGridCell vx_grid_cell(vec3 q, ivec3 dims, int floats) {
    q -= vec3(0.5f);
    vec3 hi = vec3(dims.x - 1, dims.y - 1, dims.z - 1);
    q = clamp(q, vec3(0.0f), hi);
    vec3 c = min(floor(q), max(hi - vec3(1.0f), vec3(0.0f)));
    VxGridCell cell;
    cell.base = ((int(c.z) * dims.y + int(c.y)) * dims.x + int(c.x)) * floats;
    cell.fx = min(q.x - c.x, 1.0f);
    cell.fy = min(q.y - c.y, 1.0f);
    cell.fz = min(q.z - c.z, 1.0f);
    return cell;
}

// Trilinear value `ch` of such a cell, FETCH(index) reading the grid's floats (a macro for the
// same reason as VX_TRILINEAR). Neighbours along an axis of one cell are the cell itself.
#define VX_GRID_TRILINEAR(FETCH, cell, dims, floats, ch) \
    VX_TRILERP(FETCH((cell).base + (ch)), FETCH((cell).base + (ch) + vx_grid_step(dims, floats, 1)), \
                FETCH((cell).base + (ch) + vx_grid_step(dims, floats, 2)), \
                FETCH((cell).base + (ch) + vx_grid_step(dims, floats, 1) + vx_grid_step(dims, floats, 2)), \
                FETCH((cell).base + (ch) + vx_grid_step(dims, floats, 4)), \
                FETCH((cell).base + (ch) + vx_grid_step(dims, floats, 4) + vx_grid_step(dims, floats, 1)), \
                FETCH((cell).base + (ch) + vx_grid_step(dims, floats, 4) + vx_grid_step(dims, floats, 2)), \
                FETCH((cell).base + (ch) + vx_grid_step(dims, floats, 7)), (cell).fx, (cell).fy, (cell).fz)

// Offset to the neighbour along the axes in `mask` (1 x, 2 y, 4 z; 7 all three).
VX_INLINE int vx_grid_step(ivec3 dims, int floats, int mask) {
    int sx = dims.x > 1 ? floats : 0;
    int sy = dims.y > 1 ? dims.x * floats : 0;
    int sz = dims.z > 1 ? dims.x * dims.y * floats : 0;
    return ((mask & 1) != 0 ? sx : 0) + ((mask & 2) != 0 ? sy : 0) + ((mask & 4) != 0 ? sz : 0);
}
