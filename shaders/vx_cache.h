// The light cache as the march reads it: optical depths (ambient occlusion, per-light shadow)
// stored at light-grid cell centres, trilinearly interpolated. One cell lookup per sample serves
// every channel; optical depth rather than transmittance is interpolated because it is linear in
// depth inside a homogeneous medium, so the interpolation is exact there.
#pragma once
#include "vx_optics.h"

// The trilinear cell of a sample in a grid: first float of its lowest corner and fractions.
struct VxCacheCell {
    int base;
    float fx;
    float fy;
    float fz;
};

// The trilinear cell of grid point q (cell centres at i + 0.5) in a grid of `dims` cells holding
// `floats` values per cell: first float of its lowest corner and fractions, clamped to the centres.
VxCacheCell vx_grid_cell(vec3 q, ivec3 dims, int floats) {
    q -= vec3(0.5f);
    vec3 hi = vec3(dims.x - 1, dims.y - 1, dims.z - 1);
    q = clamp(q, vec3(0.0f), hi);
    vec3 c = min(floor(q), max(hi - vec3(1.0f), vec3(0.0f)));
    VxCacheCell cell;
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

VxCacheCell vx_cache_cell(vec3 world) {
    return vx_grid_cell(vec3(P.world_to_cache * vec4(world, 1.0f)), P.cache_dims, P.cache_floats);
}

// Channel `ch` of the cache at a sample.
float vx_cache_value(VxCacheCell cell, int ch) {
    VX_CHECK_INDEX(ch, P.cache_floats, "light-cache channel");
    return VX_GRID_TRILINEAR(vx_cache, cell, P.cache_dims, P.cache_floats, ch);
}

// Ambient transmittance at a sample: exp(-tau_AO), per channel with colour bleeding.
vec3 vx_ambient_occlusion(VxCacheCell cell) {
    if (P.ao_channel < 0) return vec3(1.0f);
    if (P.ao_channels == 1) return vec3(vx_exp(-vx_cache_value(cell, P.ao_channel)));
    return vec3(vx_exp(-vx_cache_value(cell, P.ao_channel)), vx_exp(-vx_cache_value(cell, P.ao_channel + 1)),
                vx_exp(-vx_cache_value(cell, P.ao_channel + 2)));
}
