// Extinction summed-area table queries (Schlegel et al. 2011): exact box sums, ambient occlusion
// from cuboid shells (Eq. 4, 5, 8) and shadow optical depth from a cone of cuboids (Eq. 7).
//
// The SAT holds integers, not floats: each light-grid cell is quantised to a multiple of the
// plane's quantum (a power of two chosen from the plane's maximum, src/lighting/extinction_sat/summed_volume.cpp) and the
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

// Carries and borrows are comparisons, not uaddCarry/usubBorrow: no out parameters, so the CPU's
// SIMD loops keep every value in registers.
VX_INLINE VxU96 vx_u96_add(VxU96 a, VxU96 b) {
    VxU96 r;
    r.lo = a.lo + b.lo;
    uint c0 = r.lo < a.lo ? 1u : 0u;
    uint m = a.mid + b.mid;
    uint c1 = m < a.mid ? 1u : 0u;
    r.mid = m + c0;
    uint c2 = r.mid < m ? 1u : 0u;
    r.hi = a.hi + b.hi + c1 + c2;
    return r;
}

VX_INLINE VxU96 vx_u96_sub(VxU96 a, VxU96 b) {
    VxU96 r;
    r.lo = a.lo - b.lo;
    uint b0 = a.lo < b.lo ? 1u : 0u;
    uint m = a.mid - b.mid;
    uint b1 = a.mid < b.mid ? 1u : 0u;
    r.mid = m - b0;
    uint b2 = m < b0 ? 1u : 0u;
    r.hi = a.hi - b.hi - b1 - b2;
    return r;
}

// A non-negative sum below 2^96 as a float (three roundings).
VX_INLINE float vx_u96_float(VxU96 v) {
    return (float(v.hi) * 4294967296.0f + float(v.mid)) * 4294967296.0f + float(v.lo);
}

// Word w (0 = low) of SAT entry e of plane `plane`. The words are stored as separate arrays
// (plane-major, then word, then entry; x fastest) so that neighbouring cells' lookups are
// neighbouring words, which the CPU backend loads as whole SIMD vectors.
VX_INLINE int vx_sat_word_index(int plane, int w, int e) {
    return (plane * 3 + w) * (S.dims.x + 1) * (S.dims.y + 1) * (S.dims.z + 1) + e;
}

// Entry e = (z * (dims.y + 1) + y) * (dims.x + 1) + x, 0 <= x <= dims.x etc.: the sum over cells
// [0, x) x [0, y) x [0, z). The x = 0, y = 0 and z = 0 faces are zero.
VX_INLINE VxU96 vx_sat_entry(int plane, int e) {
    VxU96 v;
    v.lo = vx_sat_word(vx_sat_word_index(plane, 0, e));
    v.mid = vx_sat_word(vx_sat_word_index(plane, 1, e));
    v.hi = vx_sat_word(vx_sat_word_index(plane, 2, e));
    return v;
}

VX_INLINE int vx_sat_entry_index(int x, int y, int z) {
    return (z * (S.dims.y + 1) + y) * (S.dims.x + 1) + x;
}

// The box [a, b) from its eight corner entries, exactly: + b - (a.x) - (a.y) - (a.z) + ... - a.
// The corners lie on four x lines; `bb`, `ab`, `ba`, `aa` are the entries at x = 0 of the lines
// (y, z) = (b.y, b.z), (a.y, b.z), (b.y, a.z), (a.y, a.z), and `xa`, `xb` the box's x faces. (The
// CPU's row batches call this with per-cell x, so the loads run along the lines.)
VX_INLINE VxU96 vx_sat_lines(int plane, int bb, int ab, int ba, int aa, int xa, int xb) {
    VxU96 s = vx_sat_entry(plane, bb + xb);
    s = vx_u96_sub(s, vx_sat_entry(plane, bb + xa));
    s = vx_u96_sub(s, vx_sat_entry(plane, ab + xb));
    s = vx_u96_sub(s, vx_sat_entry(plane, ba + xb));
    s = vx_u96_add(s, vx_sat_entry(plane, ab + xa));
    s = vx_u96_add(s, vx_sat_entry(plane, ba + xa));
    s = vx_u96_add(s, vx_sat_entry(plane, aa + xb));
    return vx_u96_sub(s, vx_sat_entry(plane, aa + xa));
}

VX_INLINE float vx_sat_quantum(int plane) {
    VX_CHECK_INDEX(plane, S.planes, "SAT plane");
    return S.quantum[plane];
}

// One term of a light pass: `weight` times the sum over the box [a, b) (faces inside the grid,
// a <= b), in the plane's value units (`quantum`, vx_sat_quantum); 0 for an empty x range. Per
// cell in vx_sat_weighted_box, per lane in the CPU's row batches below: the one copy of the
// arithmetic. (The lookups are made for an empty range too, where they are in the table all the
// same: loads under a condition would be masked loads in the CPU's SIMD loops.)
VX_INLINE float vx_sat_term(int plane, float quantum, float weight, int ax, int ay, int az, int bx, int by, int bz) {
    float sum = vx_u96_float(vx_sat_lines(plane, vx_sat_entry_index(0, by, bz), vx_sat_entry_index(0, ay, bz),
                                          vx_sat_entry_index(0, by, az), vx_sat_entry_index(0, ay, az), ax, bx)) *
                quantum;
    return ax < bx ? weight * sum : 0.0f;
}

// `weight` times the sum over the cells of box [lo, hi) (clamped to the grid; cells outside are
// empty): eight lookups, exact until the final float conversion.
VX_INLINE float vx_sat_weighted_box(int plane, float weight, ivec3 lo, ivec3 hi) {
    ivec3 a = clamp(lo, ivec3(0), S.dims);
    ivec3 b = clamp(hi, ivec3(0), S.dims);
    if (a.x >= b.x || a.y >= b.y || a.z >= b.z) return 0.0f;   // (the GL per-cell queries skip the lookups)
    return vx_sat_term(plane, vx_sat_quantum(plane), weight, a.x, a.y, a.z, b.x, b.y, b.z);
}

// Both light passes are weighted sums of box sums, sum_j weight_j * SAT(c + lo_j, c + hi_j), over
// cuboids given relative to the cell c. The GL backend runs them per cell (vx_ambient_tau,
// vx_cone_tau); the CPU backend runs a row of cells at once (the row batches at the end).
struct VxCuboid {
    ivec3 lo;
    ivec3 hi;
    float weight;
};

// Ambient occlusion (Eq. 4, 5, 8): tau = sum_i (SAT(Sh_i) - SAT(Sh_i-1)) * V_cell / (24 r_i^2),
// the 1/r^2-weighted extinction in cuboid shells Sh_i of inscribed radius r_i. A cube of
// inscribed radius r has volume 8 r^3, so its shell of width dr holds 24 r^2 dr: the 1/24 (the
// cube's 4 pi) makes tau the optical depth to the neighbourhood's edge, sigma * R, in a
// homogeneous medium.
// Shell i = 1..n is the cube of 2k_i + 1 cells centred on the cell (r_i = k_i + 1/2),
// k_i = floor(i R / n): spread evenly out to the radius R; with n >= R the innermost is the cell
// itself and every ring of cells is a shell. Regrouped by cube, cube i has weight
// 1/r_i^2 - 1/r_i+1^2 (never negative, so the float sum has no cancellation; zero for a cube
// repeated when n > R).
VxCuboid vx_shell_cuboid(int i) {
    int n = S.shells;
    int k = int(floor(float(i) * S.shell_radius / float(n)));
    int k_next = int(floor(float(i + 1) * S.shell_radius / float(n)));
    float r = float(k) + 0.5f;
    float r_next = float(k_next) + 0.5f;
    VxCuboid q;
    q.lo = ivec3(-k);
    q.hi = ivec3(k + 1);
    q.weight = (1.0f / (r * r) - (i < n ? 1.0f / (r_next * r_next) : 0.0f)) * S.cell_world / 24.0f;
    return q;
}

float vx_ambient_tau(ivec3 c, int plane) {
    float tau = 0.0f;
    for (int i = 1; i <= S.shells; ++i) {
        VxCuboid q = vx_shell_cuboid(i);
        tau += vx_sat_weighted_box(plane, q.weight, c + q.lo, c + q.hi);
    }
    return tau;
}

// Shadow optical depth towards a light (Eq. 7): the cone from the cell centre to the light is
// covered by cuboids stacked along its primary axis (the axis closest to the light direction,
// Fig. 7). Each contributes its mean extinction (the paper's weight h = 1 / V_q) times the length
// of ray inside it, so a thin cone in a homogeneous medium gives exactly sigma * distance.
// VxCone is the cone seen from one cell: `wh` is the direction to the light scaled to one cell
// per primary step, `reach` the primary-axis distance the cone covers (to the light, or for
// directional lights the grid's whole extent: cuboids beyond its face read empty cells).
struct VxCone {
    vec3 wh;
    int axis;
    bool forward;           // towards +axis
    float reach;
    float step_world;       // world length of one primary step along the ray
    float wh_length;        // length(wh): cells along the ray per primary step
};

VxCone vx_cone_from(ivec3 c, VxLight L) {
    VxCone k;
    vec3 w;
    bool directional = L.type == VX_LIGHT_DIRECTIONAL;
    if (directional) w = vec3(S.world_to_light * vec4(-L.direction, 0.0f));
    else w = vec3(S.world_to_light * vec4(L.position, 1.0f)) - (vec3(c) + vec3(0.5f));
    vec3 aw = abs(w);
    k.axis = aw.x >= aw.y && aw.x >= aw.z ? 0 : (aw.y >= aw.z ? 1 : 2);
    k.forward = w[k.axis] > 0.0f;
    k.wh = aw[k.axis] > 1e-20f ? w / aw[k.axis] : vec3(0.0f);
    // Primary-axis distance from the centre to the grid's face (or the whole grid for directional
    // lights, so that every cell sees the same cuboids), and to a point or spot light.
    float to_face = directional ? float(S.dims[k.axis]) - 0.5f
                                : (k.forward ? float(S.dims[k.axis] - c[k.axis]) - 0.5f : float(c[k.axis]) + 0.5f);
    k.reach = directional ? to_face : min(aw[k.axis], to_face);
    k.step_world = length(vec3(S.light_to_world * vec4(k.wh, 0.0f)));
    k.wh_length = length(k.wh);
    return k;
}

// Primary-axis distance from the cell centre after j >= 1 of the n cuboids (they start at 1/2, the
// cell's own face): geometric in j over the grid's extent `span` (each cuboid 1 + growth times
// longer than the one before), rounded to cell faces. The same for every cell of a pass.
// `ratio_j` is (1 + growth)^j, kept by the caller's loop (pow per cuboid would dominate).
VX_INLINE float vx_cone_boundary(int j, float ratio_j, float span) {
    float n = float(S.cone_cuboids);
    float g = S.cone_growth;
    float f = g > 1e-4f ? (ratio_j - 1.0f) / (S.cone_growth_total - 1.0f) : float(j) / n;
    return 0.5f + floor(f * (span - 0.5f) + 0.5f);
}

// Cuboid covering the cone between primary distances t0 < t1, relative to the cell: along the
// primary axis the cells the segment passes through; across it the ray's extent widened by the
// cone radius at t1, rounded to cell faces and at least one cell wide.
VX_INLINE VxCuboid vx_cone_cuboid(VxCone k, float t0, float t1) {
    float radius = S.cone_tan * t1 * k.wh_length;
    vec3 e0 = vec3(0.5f) + k.wh * t0;
    vec3 e1 = vec3(0.5f) + k.wh * t1;
    VxCuboid q;
    q.lo = ivec3(floor(min(e0, e1) - vec3(radius) + vec3(0.5f)));
    q.hi = max(ivec3(floor(max(e0, e1) + vec3(radius) + vec3(0.5f))), q.lo + ivec3(1));
    float a0 = k.forward ? 0.5f + t0 : 0.5f - t1;
    float a1 = k.forward ? 0.5f + t1 : 0.5f - t0;
    q.lo[k.axis] = int(floor(a0));
    q.hi[k.axis] = max(int(ceil(a1)), q.lo[k.axis] + 1);
    ivec3 size = q.hi - q.lo;
    q.weight = (t1 - t0) * k.step_world / (float(size.x) * float(size.y) * float(size.z));
    return q;
}

// The cell's own contribution: its extinction over the distance to its face (or to the light).
VxCuboid vx_cone_own_cell(VxCone k) {
    VxCuboid q;
    q.lo = ivec3(0);
    q.hi = ivec3(1);
    q.weight = min(0.5f, k.reach) * k.step_world;
    return q;
}

// The cone's own-cell term, or 0 when the light is at the cell's centre.
VX_INLINE float vx_cone_start(ivec3 c, VxCone k) {
    if (k.reach <= 0.0f || k.step_world <= 0.0f) return 0.0f;
    VxCuboid own = vx_cone_own_cell(k);
    return vx_sat_weighted_box(0, own.weight, c + own.lo, c + own.hi);
}

// A walk along a cone's cuboids: the one cone loop, which the GL pass, the CPU's row batches
// and vx_cone_tau share. `j` counts the cuboids so far, `ratio_j` is (1 + growth)^j (kept
// rather than pow per cuboid, which would dominate), `t0` where the last cuboid ended (1/2, the
// cell's own face, before the first).
struct VxConeWalk {
    int j;
    float ratio_j;
    float t0;
};

VX_INLINE VxConeWalk vx_cone_walk_begin() {
    VxConeWalk w;
    w.j = 0;
    w.ratio_j = 1.0f;
    w.t0 = 0.5f;
    return w;
}

// Steps to the walk's next cuboid (S.cone_cuboids steps in all) and puts it in `q`. False past
// the light or for an empty cuboid.
VX_INLINE bool vx_cone_step(VxCone k, VX_INOUT(VxConeWalk) w, VX_OUT(VxCuboid) q) {
    w.j += 1;
    w.ratio_j *= 1.0f + S.cone_growth;
    if (w.t0 >= k.reach || k.step_world <= 0.0f) return false;
    float t1 = min(vx_cone_boundary(w.j, w.ratio_j, float(S.dims[k.axis]) - 0.5f), k.reach);
    if (t1 <= w.t0) return false;
    q = vx_cone_cuboid(k, w.t0, t1);
    w.t0 = t1;
    return true;
}

float vx_cone_tau(ivec3 c, VxLight L) {
    VxCone k = vx_cone_from(c, L);
    float tau = vx_cone_start(c, k);
    VxConeWalk w = vx_cone_walk_begin();
    for (int j = 1; j <= S.cone_cuboids; ++j) {
        VxCuboid q;
        if (vx_cone_step(k, w, q)) tau += vx_sat_weighted_box(0, q.weight, c + q.lo, c + q.hi);
    }
    return tau;
}

// The CPU's row batches: the cells c0 + (i, 0, 0) of a grid row, whose lookups along the lines
// are neighbouring words. Each lane adds the same vx_sat_term, in the same order, as the
// per-cell queries above. Widths: one AVX-512 vector of 32-bit words for shared cuboids; two for
// cones, whose gathers then overlap more (docs/accuracy-sat.md, measured with
// voxlux_bench_sat --paper-only).
#define VX_SAT_ROW 16
#define VX_CONE_ROW 32

struct VxSatRow {
    float tau[VX_SAT_ROW];
};

// Whether every lane of the row from c0's x reads cuboid q's x range inside the grid, so that
// vx_sat_add_cuboid_row may take it unclamped.
VX_INLINE bool vx_sat_row_inside(VxCuboid q, int x0) { return x0 + q.lo.x >= 0 && x0 + VX_SAT_ROW - 1 + q.hi.x <= S.dims.x; }

// One cuboid every cell shares (an AO shell, a directional light's cone cuboid) across a row:
// tau[i] += vx_sat_weighted_box(plane, q.weight, c0 + (i, 0, 0) + q.lo, ... + q.hi). With `clamp_x`
// false (vx_sat_row_inside) the loads are contiguous. A plain loop, not
// VX_SIMD_LOOP: `omp simd` would privatise the VxU96 temporaries into memory before they are
// inlined away; the auto-vectoriser, which runs after inlining, keeps them in registers.
VX_INLINE void vx_sat_add_cuboid_row(int plane, VxCuboid q, ivec3 c0, bool clamp_x, VX_INOUT(VxSatRow) row) {
    int ay = clamp(c0.y + q.lo.y, 0, S.dims.y);
    int by = clamp(c0.y + q.hi.y, 0, S.dims.y);
    int az = clamp(c0.z + q.lo.z, 0, S.dims.z);
    int bz = clamp(c0.z + q.hi.z, 0, S.dims.z);
    if (ay >= by || az >= bz) return;
    float quantum = vx_sat_quantum(plane);
    float weight = q.weight;
    for (int i = 0; i < VX_SAT_ROW; ++i) {
        int xa = c0.x + q.lo.x + i;
        int xb = c0.x + q.hi.x + i;
        xa = clamp_x ? clamp(xa, 0, S.dims.x) : xa;
        xb = clamp_x ? clamp(xb, 0, S.dims.x) : xb;
        row.tau[i] += vx_sat_term(plane, quantum, weight, xa, ay, az, xb, by, bz);
    }
}

// vx_cone_tau for the cells c0 + (i, 0, 0), i < VX_CONE_ROW, whose bit i of `needed` is set (the
// others get 0): the cones towards a point or spot light, which differ per cell. Each lane walks
// its own cone (scalar geometry: vx_cone_row_boxes), then the row's boxes of that cuboid are
// summed at once, a gather per corner word (vx_cone_row_add). The caller takes every row of a
// grid row through one stage before the next, so that one cuboid's lookups run along the grid row
// and many gathers are in flight together.
struct VxConeRow {
    ivec3 c0;
    uint needed;
    VxCone cones[VX_CONE_ROW];
    VxConeWalk walks[VX_CONE_ROW];
    // Each lane's current box clamped to the grid (an empty one at 0 for a lane without a
    // cuboid), as separate arrays so that the sums vectorise.
    int ax[VX_CONE_ROW];
    int ay[VX_CONE_ROW];
    int az[VX_CONE_ROW];
    int bx[VX_CONE_ROW];
    int by[VX_CONE_ROW];
    int bz[VX_CONE_ROW];
    float weight[VX_CONE_ROW];
    float tau[VX_CONE_ROW];
};

VX_INLINE bool vx_cone_row_needs(VX_IN(VxConeRow) r, int i) { return ((r.needed >> uint(i)) & 1u) != 0u; }

// The cones and their own-cell terms (vx_cone_start).
void vx_cone_row_begin(ivec3 c0, VxLight L, uint needed, VX_OUT(VxConeRow) r) {
    r.c0 = c0;
    r.needed = needed;
    for (int i = 0; i < VX_CONE_ROW; ++i) {
        ivec3 c = c0 + ivec3(i, 0, 0);
        r.cones[i] = vx_cone_from(c, L);
        r.walks[i] = vx_cone_walk_begin();
        r.tau[i] = vx_cone_row_needs(r, i) ? vx_cone_start(c, r.cones[i]) : 0.0f;
    }
}

// Every lane's next cuboid (one of vx_cone_tau's S.cone_cuboids steps, vx_cone_step) as its box.
VX_INLINE void vx_cone_row_boxes(VX_INOUT(VxConeRow) r) {
    for (int i = 0; i < VX_CONE_ROW; ++i) {
        ivec3 c = r.c0 + ivec3(i, 0, 0);
        VxCuboid q;
        bool on = vx_cone_row_needs(r, i) && vx_cone_step(r.cones[i], r.walks[i], q);
        ivec3 a = on ? clamp(c + q.lo, ivec3(0), S.dims) : ivec3(0);
        ivec3 b = on ? max(clamp(c + q.hi, ivec3(0), S.dims), a) : ivec3(0);
        r.ax[i] = a.x;
        r.ay[i] = a.y;
        r.az[i] = a.z;
        r.bx[i] = b.x;
        r.by[i] = b.y;
        r.bz[i] = b.z;
        r.weight[i] = on ? q.weight : 0.0f;
    }
}

// The boxes' terms, added.
VX_INLINE void vx_cone_row_add(VX_INOUT(VxConeRow) r) {
    float quantum = vx_sat_quantum(0);
    for (int i = 0; i < VX_CONE_ROW; ++i)
        r.tau[i] += vx_sat_term(0, quantum, r.weight[i], r.ax[i], r.ay[i], r.az[i], r.bx[i], r.by[i], r.bz[i]);
}
