// Brick addressing and reconstruction: page-table lookup, and the atlas filtered between voxels
// (P.voxel_filter): trilinear, 8 voxel reads per sample, or the cubic B-spline, 8 trilinear taps (64
// reads) and up to 7 page-table lookups where the taps cross into neighbouring bricks.
#pragma once
#include "vx_types.h"

// The value stored for `key` in the open-addressed table at page entries [first, first +
// capacity) (vx_brick_hash, linear probing), or VX_PAGE_EMPTY.
VX_INLINE int vx_table_find(ivec3 key, int first, int capacity, int max_probe) {
    uint mask = uint(capacity - 1);
    uint h = vx_brick_hash(key) & mask;
    for (int probe = 0; probe <= max_probe; ++probe) {
        ivec4 e = vx_page_entry(first + int(h));
        if (e.w == VX_PAGE_EMPTY) return VX_PAGE_EMPTY;
        if (e.x == key.x && e.y == key.y && e.z == key.z) return e.w;
        h = (h + 1u) & mask;
    }
    return VX_PAGE_EMPTY;
}

// The one volume's pages: the whole table, after which come the regions'.
VX_INLINE VxPageRange vx_own_pages() {
    VxPageRange r;
    r.lo = P.bricks_min;
    r.first = 0;
    r.hi = P.bricks_max;
    r.capacity = P.page_capacity;
    r.max_probe = P.page_max_probe;
    r.pad0 = 0;
    r.pad1 = 0;
    r.pad2 = 0;
    return r;
}

// Atlas slot of brick `b` among pages `r`, or VX_PAGE_EMPTY.
VX_INLINE int vx_page_lookup_in(VxPageRange r, ivec3 b) {
    // Compared axis by axis: GLM's any(lessThan()) stays an out-of-line call in the CPU's long
    // per-sample functions (a twentieth of a tricubic shadow ray's time).
    if (b.x < r.lo.x || b.y < r.lo.y || b.z < r.lo.z || b.x > r.hi.x || b.y > r.hi.y || b.z > r.hi.z) return VX_PAGE_EMPTY;
    return vx_table_find(b, r.first, r.capacity, r.max_probe);
}

// Atlas slot of brick `b` of the one volume, or VX_PAGE_EMPTY.
VX_INLINE int vx_page_lookup(ivec3 b) {
    return vx_page_lookup_in(vx_own_pages(), b);
}

// Whether region `r` (VX_REGION_BRICKS^3 bricks, vx_region_of) holds any brick of the
// page table. The regions' table follows the bricks' in the page entries.
VX_INLINE bool vx_region_occupied(ivec3 r) {
    return vx_table_find(r, P.page_capacity, P.region_capacity, P.region_max_probe) != VX_PAGE_EMPTY;
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

// A sample's reconstruction: the trilinear cells it reads and how it weighs them. Trilinear is
// one cell. The cubic B-spline (Sigg and Hadwiger 2005, GPU Gems 2 ch. 20) folds the 4 B-spline
// weights per axis into 2 trilinear taps, at i - 1 + w1 / (w0 + w1) and i + 1 + w3 / (w2 + w3),
// weighted w0 + w1 and w2 + w3: 8 taps combined trilinearly with fractions s. A tap in a brick
// missing from the page table reads 0 (present = 0); under this filter the page table holds every
// stored neighbour of a visible brick (classifiedPageTable), so that is a brick with no active values
// in any grid, which the march does not enter either. The B-spline is a
// convex combination of the 4^3 voxels around the sample: smooth (C2), never overshooting, and a
// little softer than the data (it does not interpolate it).
struct VxTaps {
    VxCorners tap[8];    // tap j at (h[j & 1].x, h[(j >> 1) & 1].y, h[(j >> 2) & 1].z)
    float present[8];    // 1, or 0 for a tap in a brick that is not stored
    float sx;            // weight of the second tap per axis
    float sy;
    float sz;
    int count;           // 1 (trilinear) or 8
};

// The single trilinear cell c as a reconstruction.
VX_INLINE VxTaps vx_single_tap(VxCorners c) {
    VxTaps r;
    r.tap[0] = c;
    r.present[0] = 1.0f;
    r.sx = 0.0f;
    r.sy = 0.0f;
    r.sz = 0.0f;
    r.count = 1;
    return r;
}

// The filter a kernel build runs. GL compiles one march program per filter, with VX_ATLAS_FILTER
// defined (src/backend/gl), so that a program holds only its own filter's code: llvmpipe takes
// minutes to compile both into one. The C++ build follows P.voxel_filter.
#ifdef VX_GLSL
#ifndef VX_ATLAS_FILTER
#define VX_ATLAS_FILTER VX_FILTER_TRILINEAR
#endif
#define VX_VOXEL_FILTER VX_ATLAS_FILTER
#else
#define VX_VOXEL_FILTER P.voxel_filter
#endif

// The cubic B-spline's weights, per axis, of the four grid points i - 1, i, i + 1, i + 2 around a
// point at fraction t past i. They sum to 1 and are never negative.
struct VxSplineWeights {
    vec3 w0;
    vec3 w1;
    vec3 w2;
    vec3 w3;
};

VX_INLINE VxSplineWeights vx_spline_weights(vec3 t) {
    vec3 t2 = t * t;
    vec3 t3 = t2 * t;
    vec3 u = 1.0f - t;
    VxSplineWeights w;
    w.w0 = u * u * u / 6.0f;    // (1 - t)^3 / 6, not expanded: it would cancel to below 0 near t = 1
    w.w1 = (4.0f - 6.0f * t2 + 3.0f * t3) / 6.0f;
    w.w3 = t3 / 6.0f;
    w.w2 = 1.0f - w.w0 - w.w1 - w.w3;
    return w;
}

// Reconstruction of the atlas at index point p inside stored brick b (atlas slot `slot`) of the
// volume whose pages are `pages`.
VX_INLINE VxTaps vx_taps_in(VxPageRange pages, int slot, ivec3 b, vec3 p) {
    if (VX_VOXEL_FILTER == VX_FILTER_TRILINEAR) return vx_single_tap(vx_corners_at(slot, b, p));
    vec3 i = floor(p);
    VxSplineWeights w = vx_spline_weights(p - i);
    vec3 g1 = w.w2 + w.w3;    // at least 1/6
    vec3 h0 = i - 1.0f + w.w1 / (w.w0 + w.w1);
    vec3 h1 = i + 1.0f + w.w3 / g1;
    VxTaps r;
    r.sx = g1.x;
    r.sy = g1.y;
    r.sz = g1.z;
    r.count = 8;
    for (int j = 0; j < 8; ++j) {
        vec3 q = vec3((j & 1) != 0 ? h1.x : h0.x, (j & 2) != 0 ? h1.y : h0.y, (j & 4) != 0 ? h1.z : h0.z);
        ivec3 qb = ivec3(floor(q / float(VX_BRICK)));
        int qs = all(equal(qb, b)) ? slot : vx_page_lookup_in(pages, qb);
        r.present[j] = qs == VX_PAGE_EMPTY ? 0.0f : 1.0f;
        r.tap[j] = vx_corners_at(qs == VX_PAGE_EMPTY ? slot : qs, qb, q);    // absent: any stored cell, weighted 0
    }
    return r;
}

// The same in the one volume.
VX_INLINE VxTaps vx_taps_at(int slot, ivec3 b, vec3 p) {
    return vx_taps_in(vx_own_pages(), slot, b, p);
}

// The same reconstruction shifted to another channel block of the atlas (emission sources).
VX_INLINE VxTaps vx_taps_offset(VxTaps r, int offset) {
    for (int j = 0; j < r.count; ++j) r.tap[j].base += offset;
    return r;
}

// A function NAME(VxTaps) returning atlas channel FETCH (as for VX_TRILINEAR) of type T,
// reconstructed: one per channel, so each expands the taps once.
#define VX_DEFINE_RECONSTRUCT(T, NAME, FETCH)                                                         \
    VX_INLINE T NAME(VxTaps r) {                                                                      \
        if (r.count == 1) return VX_TRILINEAR(FETCH, r.tap[0]);                                       \
        T v[8];                                                                                       \
        for (int j = 0; j < 8; ++j) v[j] = r.present[j] * VX_TRILINEAR(FETCH, r.tap[j]);             \
        return VX_TRILERP(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], r.sx, r.sy, r.sz);         \
    }
VX_DEFINE_RECONSTRUCT(float, vx_density_at, vx_atlas_density)
VX_DEFINE_RECONSTRUCT(float, vx_emission_value_at, vx_atlas_emission)
VX_DEFINE_RECONSTRUCT(vec3, vx_color_at, vx_atlas_color)
VX_DEFINE_RECONSTRUCT(float, vx_surface_weight_at, vx_atlas_surface)

// World points and directions in the grid's index space.
vec3 vx_to_index_point(vec3 x) { return vec3(P.world_to_index * vec4(x, 1.0f)); }
vec3 vx_to_index_dir(vec3 v) { return vec3(P.world_to_index * vec4(v, 0.0f)); }

// Raw density at index point p from whichever brick holds it (0 in empty bricks): for lookups
// that may leave the brick being marched (displaced samples, gradients).
float vx_density_index(vec3 p) {
    ivec3 b = ivec3(floor(p / float(VX_BRICK)));
    int slot = vx_page_lookup(b);
    if (slot == VX_PAGE_EMPTY) return 0.0f;
    return vx_density_at(vx_taps_at(slot, b, p));
}
