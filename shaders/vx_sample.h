// Brick addressing and reconstruction: page-table lookup and trilinear fetch from the atlas.
#pragma once
#include "vx_types.h"

// Atlas slot of brick `b`, or VX_PAGE_EMPTY.
VX_INLINE int vx_page_lookup(ivec3 b) {
    if (any(lessThan(b, P.bricks_min)) || any(greaterThan(b, P.bricks_max)))
        return VX_PAGE_EMPTY;
    uint mask = uint(P.page_capacity - 1);
    uint h = vx_brick_hash(b) & mask;
    for (int probe = 0; probe <= P.page_max_probe; ++probe) {
        ivec4 e = vx_page_entry(int(h));
        if (e.w == VX_PAGE_EMPTY) return VX_PAGE_EMPTY;
        if (e.x == b.x && e.y == b.y && e.z == b.z) return e.w;
        h = (h + 1u) & mask;
    }
    return VX_PAGE_EMPTY;
}

// The trilinear cell of a point at brick-local index coordinates (lx, ly, lz) (the point minus
// the brick's first voxel): the atlas offset of its lowest corner and the fractional position. Points that round onto the next brick's first voxel
// are clamped to weight 1 on the apron, which holds exactly that voxel, so the result stays exact.
// Plain floats rather than vectors keep the CPU's SIMD batches (vx_chunk_extinction) vectorisable.
struct VxCorners {
    int base;
    float fx;
    float fy;
    float fz;
};

VX_INLINE VxCorners vx_corners(int slot, float lx, float ly, float lz) {
    float cx = clamp(floor(lx), 0.0f, float(VX_BRICK - 1));
    float cy = clamp(floor(ly), 0.0f, float(VX_BRICK - 1));
    float cz = clamp(floor(lz), 0.0f, float(VX_BRICK - 1));
    VxCorners c;
    c.base = slot * VX_BRICK_VOXELS + (int(cz) * VX_BRICK_STRIDE + int(cy)) * VX_BRICK_STRIDE + int(cx);
    c.fx = clamp(lx - cx, 0.0f, 1.0f);
    c.fy = clamp(ly - cy, 0.0f, 1.0f);
    c.fz = clamp(lz - cz, 0.0f, 1.0f);
    return c;
}

// The same for index-space point `p` inside brick `b`.
VX_INLINE VxCorners vx_corners_at(int slot, ivec3 b, vec3 p) {
    vec3 local = p - vec3(b * VX_BRICK);
    return vx_corners(slot, local.x, local.y, local.z);
}

// The interpolation filters, the only copies: c_xyz is the value at corner (x, y, z) of a unit
// cell, fx, fy, fz the position in it. Any type mix() takes (float, vec3, vec4); macros because
// GLSL has no generics. Every lookup of the kernel (atlas, light cache, illumination volume,
// noise, propagation grids) and the CPU's row batches filter with these.
#define VX_BILERP(c00, c10, c01, c11, fx, fy) mix(mix(c00, c10, fx), mix(c01, c11, fx), fy)
#define VX_TRILERP(c000, c100, c010, c110, c001, c101, c011, c111, fx, fy, fz) \
    mix(VX_BILERP(c000, c100, c010, c110, fx, fy), VX_BILERP(c001, c101, c011, c111, fx, fy), fz)

// Trilinear reconstruction of any atlas channel: FETCH is an accessor taking an atlas index
// (strides: +1 in x, +9 in y, +81 in z).
#define VX_TRILINEAR(FETCH, c) \
    VX_TRILERP(FETCH((c).base), FETCH((c).base + 1), FETCH((c).base + 9), FETCH((c).base + 10), \
               FETCH((c).base + 81), FETCH((c).base + 82), FETCH((c).base + 90), FETCH((c).base + 91), \
               (c).fx, (c).fy, (c).fz)

// Raw density at index point p from whichever brick holds it (0 in empty bricks): for lookups
// that may leave the brick being marched (displaced samples, gradients).
float vx_density_index(vec3 p) {
    ivec3 b = ivec3(floor(p / float(VX_BRICK)));
    int slot = vx_page_lookup(b);
    if (slot == VX_PAGE_EMPTY) return 0.0f;
    return VX_TRILINEAR(vx_atlas_density, vx_corners_at(slot, b, p));
}
