// Brick addressing and reconstruction: page-table lookup and trilinear fetch from the atlas.
#pragma once
#include "vx_types.h"

// Spatial hash of a brick coordinate. The page table is open-addressed with linear probing,
// so its size follows the number of occupied bricks, never the bounding box.
uint vx_brick_hash(ivec3 b) {
    return (uint(b.x) * 73856093u) ^ (uint(b.y) * 19349663u) ^ (uint(b.z) * 83492791u);
}

// Atlas slot of brick `b`, or VX_PAGE_EMPTY.
int vx_page_lookup(ivec3 b) {
    if (b.x < P.bricks_min.x || b.y < P.bricks_min.y || b.z < P.bricks_min.z ||
        b.x > P.bricks_max.x || b.y > P.bricks_max.y || b.z > P.bricks_max.z)
        return VX_PAGE_EMPTY;
    uint mask = uint(P.page.x - 1);
    uint h = vx_brick_hash(b) & mask;
    for (int probe = 0; probe <= P.page.y; ++probe) {
        ivec4 e = vx_page_entry(int(h));
        if (e.w == VX_PAGE_EMPTY) return VX_PAGE_EMPTY;
        if (e.x == b.x && e.y == b.y && e.z == b.z) return e.w;
        h = (h + 1u) & mask;
    }
    return VX_PAGE_EMPTY;
}

// The eight trilinear corners of index-space point `p` inside brick `b`: the offset of the lowest
// corner in the atlas and the corner weights (lo = the z0 face, hi = the z1 face, each ordered
// (x0y0, x1y0, x0y1, x1y1)). Points that round onto the next brick's first voxel are clamped to
// weight 1 on the apron, which holds exactly that voxel, so the result stays exact.
struct VxCorners {
    int base;
    vec4 lo;
    vec4 hi;
};

VxCorners vx_corners(int slot, ivec3 b, vec3 p) {
    vec3 local = p - vec3(b * VX_BRICK);
    ivec3 cell = clamp(ivec3(floor(local)), ivec3(0), ivec3(VX_BRICK - 1));
    vec3 f = clamp(local - vec3(cell), vec3(0.0f), vec3(1.0f));
    vec4 xy = vec4((1.0f - f.x) * (1.0f - f.y), f.x * (1.0f - f.y), (1.0f - f.x) * f.y, f.x * f.y);
    VxCorners c;
    c.base = slot * VX_BRICK_VOXELS + (cell.z * VX_BRICK_STRIDE + cell.y) * VX_BRICK_STRIDE + cell.x;
    c.lo = xy * (1.0f - f.z);
    c.hi = xy * f.z;
    return c;
}

// One trilinear reconstruction for any atlas channel: FETCH is an accessor taking an atlas index.
// A macro because GLSL has no generics; it is the only copy of the filter.
#define VX_TRILINEAR(FETCH, c) \
    ((c).lo.x * FETCH((c).base) + (c).lo.y * FETCH((c).base + 1) + \
     (c).lo.z * FETCH((c).base + 9) + (c).lo.w * FETCH((c).base + 10) + \
     (c).hi.x * FETCH((c).base + 81) + (c).hi.y * FETCH((c).base + 82) + \
     (c).hi.z * FETCH((c).base + 90) + (c).hi.w * FETCH((c).base + 91))
