// The light cache as the march reads it: optical depths (ambient occlusion, per-light shadow)
// stored at light-grid cell centres, trilinearly interpolated. One cell lookup per sample serves
// every channel; optical depth rather than transmittance is interpolated because it is linear in
// depth inside a homogeneous medium, so the interpolation is exact there.
#pragma once
#include "vx_optics.h"

// The trilinear cell of a sample in the cache: first float of its lowest corner and fractions.
struct VxCacheCell {
    int base;
    float fx;
    float fy;
    float fz;
};

VxCacheCell vx_cache_cell(vec3 world) {
    vec3 q = vec3(P.world_to_cache * vec4(world, 1.0f)) - vec3(0.5f);
    vec3 hi = vec3(P.cache_dims.x - 1, P.cache_dims.y - 1, P.cache_dims.z - 1);
    q = clamp(q, vec3(0.0f), hi);
    vec3 c = min(floor(q), max(hi - vec3(1.0f), vec3(0.0f)));
    VxCacheCell cell;
    cell.base = ((int(c.z) * P.cache_dims.y + int(c.y)) * P.cache_dims.x + int(c.x)) * P.cache_dims.w;
    cell.fx = min(q.x - c.x, 1.0f);
    cell.fy = min(q.y - c.y, 1.0f);
    cell.fz = min(q.z - c.z, 1.0f);
    return cell;
}

// Channel `ch` of the cache at a sample. Neighbours along an axis of one cell are the cell itself.
float vx_cache_value(VxCacheCell cell, int ch) {
    int sx = P.cache_dims.x > 1 ? P.cache_dims.w : 0;
    int sy = P.cache_dims.y > 1 ? P.cache_dims.x * P.cache_dims.w : 0;
    int sz = P.cache_dims.z > 1 ? P.cache_dims.x * P.cache_dims.y * P.cache_dims.w : 0;
    int b = cell.base + ch;
    return mix(mix(mix(vx_cache(b), vx_cache(b + sx), cell.fx), mix(vx_cache(b + sy), vx_cache(b + sy + sx), cell.fx), cell.fy),
               mix(mix(vx_cache(b + sz), vx_cache(b + sz + sx), cell.fx),
                   mix(vx_cache(b + sz + sy), vx_cache(b + sz + sy + sx), cell.fx), cell.fy),
               cell.fz);
}

// Ambient transmittance at a sample: exp(-tau_AO), per channel with colour bleeding.
vec3 vx_ambient_occlusion(VxCacheCell cell) {
    if (P.cache_map.x < 0) return vec3(1.0f);
    if (P.cache_map.y == 1) return vec3(vx_exp(-vx_cache_value(cell, P.cache_map.x)));
    return vec3(vx_exp(-vx_cache_value(cell, P.cache_map.x)), vx_exp(-vx_cache_value(cell, P.cache_map.x + 1)),
                vx_exp(-vx_cache_value(cell, P.cache_map.x + 2)));
}
