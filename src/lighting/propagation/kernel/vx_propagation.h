// Illumination propagation (Ropinski 2010, Sec. 4.1, with the Kniss 2003 optical model): one
// cell of one slice of a sweep (VxPropParams Q). The slice's value is computed from the previous
// slice where the ray from the light (or, for the eye sweep, towards the camera) crosses it:
//  - direct sweep (1 channel): luminance, one bilinear read, no blur, so shadow edges stay hard;
//  - indirect sweep (3 channels): RGB blurred over Q.tap_count taps in a cone (Kniss Eq. 9) and
//    attenuated by the transport colour (Kniss Eq. 8): one for the whole medium (Q.atten), or
//    per material (Q.transport_planes: a 2D transfer function's regions);
//  - eye sweep (3 channels): the indirect light blended with the blurred light behind the cell;
//  - source sweep (3 channels, Q.source_sweep): nothing enters from outside; every cell adds its
//    own source along the step (emitted light, or light scattered once, that then travels on).
// The optical depth of a step is the trapezoid rule over the extinction along it times its world
// length, so it is corrected for the slice distance and the propagation angle alike.
// Several lights share the volume (Sunden 2015): each sweep adds vx_prop_weight times its value,
// tinted by Q.tint, so a negative weight takes a light out again.
// Accessors: vx_prop_sigma (the sweep grid's extinction per world unit, one float per cell; with
// per-material transport three more planes follow, extinction times -ln(transport colour)),
// vx_prop_prev (the previous slice, Q.channels floats per cell), vx_prop_in (the eye sweep's input
// or a source sweep's source, 3 floats per cell of the whole grid), vx_noise (perturbation table).
#pragma once
#include "vx_noise.h"

// The two in-slice axes of a sweep along `axis`: u, the lower one, runs fastest in a slice, so
// that a slice of a y or z sweep is rows of x, contiguous in memory.
VX_INLINE int vx_axis_u(int axis) { return axis == 0 ? 1 : 0; }
VX_INLINE int vx_axis_v(int axis) { return axis == 2 ? 1 : 2; }

// The share of light flowing along f (grid space) that the sweep along `axis` in direction `sign`
// carries: 1 on the principal axis, the one f is closest to (ties go to z, then y), else 0. With
// `blend`, the light is split between its two closest axes by the angles theta_i to them:
// w0 ~ theta_2 - theta_0, w1 ~ theta_2 - theta_1, which in the plane of the two axes is Sunden's
// Eq. 5a/5b (w0 = 1 - 2 theta_0 / pi) and off it stays continuous where the second and third axes
// swap. The second axis fades out between slopes VX_PROP_MAX_SLOPE / 2 and VX_PROP_MAX_SLOPE (it
// carries under 8% there), so no sweep steps further sideways than that.
VX_INLINE float vx_sweep_weight(vec3 f, int axis, int sign, bool blend) {
    if (float(sign) * f[axis] <= 0.0f) return 0.0f;
    vec3 a = abs(f);
    int p = a.z >= a.y && a.z >= a.x ? 2 : (a.y >= a.x ? 1 : 0);
    if (!blend) return axis == p ? 1.0f : 0.0f;
    int lo = p == 0 ? 1 : 0;
    int hi = p == 2 ? 1 : 2;
    int s = a[hi] >= a[lo] ? hi : lo;
    int t = s == hi ? lo : hi;
    float len = length(f);
    float t0 = acos(min(a[p] / len, 1.0f));
    float t1 = acos(min(a[s] / len, 1.0f));
    float t2 = acos(min(a[t] / len, 1.0f));
    float w0 = t2 - t0;
    float w1 = t2 - t1;
    // On a body diagonal all three angles are equal: any split of two axes is as good as another.
    if (w0 + w1 <= 1e-7f) {
        w0 = 0.5f;
        w1 = 0.5f;
    }
    w1 *= clamp(VX_PROP_MAX_SLOPE * a[s] / a[p] - 1.0f, 0.0f, 1.0f);
    return (axis == p ? w0 : (axis == s ? w1 : 0.0f)) / (w0 + w1);
}

// The functions below that take the sweep's `axis` (Q.axis) as an argument are the ones the CPU's
// row batches call with a constant: inlined, a vector's component along it then needs no select.

// Grid point with coordinate s along the sweep axis and (a, b) along u and v.
VX_INLINE vec3 vx_prop_point(int axis, float s, float a, float b) {
    vec3 q;
    q[axis] = s;
    q[vx_axis_u(axis)] = a;
    q[vx_axis_v(axis)] = b;
    return q;
}

// Grid cell s along the sweep axis and (i, j) along u and v (vx_prop_point's cell).
VX_INLINE ivec3 vx_prop_cell_at(int axis, int s, int i, int j) {
    ivec3 c = ivec3(0);   // (every component is set below; the compiler cannot tell with a run-time axis)
    c[axis] = s;
    c[vx_axis_u(axis)] = i;
    c[vx_axis_v(axis)] = j;
    return c;
}

// Where cell c's values are in the sweep's extinction grid and eye input (Q.strides: the CPU lays
// an x sweep's grid out slice by slice).
VX_INLINE int vx_prop_index(ivec3 c) { return c.x * Q.strides.x + c.y * Q.strides.y + c.z * Q.strides.z; }

// Where plane `plane` of the extinction has cell c (vx_prop_sigma).
VX_INLINE int vx_prop_sigma_index(ivec3 c, int plane) { return plane * Q.dims.x * Q.dims.y * Q.dims.z + vx_prop_index(c); }

// Plane `plane` of the extinction (0: extinction per world unit; 1-3: times -ln(transport colour)
// per channel) at grid cell c, unperturbed; 0 outside the grid.
VX_INLINE float vx_prop_sigma_cell(ivec3 c, int plane) {
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= Q.dims.x || c.y >= Q.dims.y || c.z >= Q.dims.z) return 0.0f;
    return vx_prop_sigma(vx_prop_sigma_index(c, plane));
}

// A plane of the extinction at grid point q, trilinear between cell centres (0 beyond the grid).
VX_INLINE float vx_prop_sigma_at(vec3 q, int plane) {
    vec3 g = q - vec3(0.5f);
    vec3 f = floor(g);
    vec3 t = g - f;
    ivec3 c = ivec3(f);
    return VX_TRILERP(vx_prop_sigma_cell(c, plane), vx_prop_sigma_cell(c + ivec3(1, 0, 0), plane),
                      vx_prop_sigma_cell(c + ivec3(0, 1, 0), plane), vx_prop_sigma_cell(c + ivec3(1, 1, 0), plane),
                      vx_prop_sigma_cell(c + ivec3(0, 0, 1), plane), vx_prop_sigma_cell(c + ivec3(1, 0, 1), plane),
                      vx_prop_sigma_cell(c + ivec3(0, 1, 1), plane), vx_prop_sigma_cell(c + ivec3(1, 1, 1), plane), t.x, t.y, t.z);
}

// A plane of the extinction at in-slice coordinates (a, b) of slice `slice`, bilinear between
// cell centres.
VX_INLINE float vx_prop_sigma_slice(int axis, float a, float b, int slice, int plane) {
    float ga = a - 0.5f;
    float gb = b - 0.5f;
    float fa = floor(ga);
    float fb = floor(gb);
    ivec3 c = vx_prop_cell_at(axis, slice, int(fa), int(fb));
    ivec3 du = vx_prop_cell_at(axis, 0, 1, 0);
    ivec3 dv = vx_prop_cell_at(axis, 0, 0, 1);
    float ta = ga - fa;
    return VX_BILERP(vx_prop_sigma_cell(c, plane), vx_prop_sigma_cell(c + du, plane), vx_prop_sigma_cell(c + dv, plane),
                     vx_prop_sigma_cell(c + du + dv, plane), ta, gb - fb);
}

// A plane of the extinction the sweep sees at grid point q: perturbed as the march perturbs it
// (the same world noise), so shadows follow the added detail. `n` is the noise at q.
VX_INLINE float vx_prop_extinction(vec3 q, vec4 n, int plane) {
    if (!vx_perturbed()) return vx_prop_sigma_at(q, plane);
    // Displacement is in index voxels; Q.cells_per_voxel converts to grid cells.
    vec3 shifted = vx_displaced() ? q + vec3(n) * (P.displacement * Q.cells_per_voxel) : q;
    return vx_perturb_extinction(vx_prop_sigma_at(shifted, plane), n);
}

VX_INLINE vec4 vx_prop_noise(vec3 q) {
    return vx_perturbed() ? vx_noise_fbm(vec3(Q.grid_to_world * vec4(q, 1.0f))) : vec4(0.0f);
}

// Point-light falloff clamps at half a cell: a light inside a cell stays finite.
VX_INLINE float vx_prop_r_min() { return 0.5f * length(vec3(Q.grid_to_world * vec4(1.0f, 0.0f, 0.0f, 0.0f))); }

// A point or spot light's sweep carries radiance times the squared distance to the light (its
// intensity times the transmittance so far): smooth where the radiance itself is singular, so
// the bilinear reads stay accurate next to the light. This is the factor between the two.
VX_INLINE float vx_prop_distance2(vec3 q) {
    vec3 r = mat3(Q.grid_to_world) * (q - Q.source);
    float r_min = vx_prop_r_min();
    return max(dot(r, r), r_min * r_min);
}

// What enters from beyond the grid at grid point q: the light's unattenuated radiance (a light
// sweep; luminance in x for the direct sweep; for a point or spot light times vx_prop_distance2),
// or the eye sweep's own input at the nearest cell; nothing for a source sweep.
vec3 vx_prop_outside(vec3 q) {
    if (Q.source_sweep != 0) return vec3(0.0f);
    if (Q.eye_sweep != 0) {
        ivec3 c = clamp(ivec3(floor(q)), ivec3(0), Q.dims - ivec3(1));
        int i = 3 * vx_prop_index(c);
        return vec3(vx_prop_in(i), vx_prop_in(i + 1), vx_prop_in(i + 2));
    }
    vec3 wi;
    float dist;
    vec3 e = vx_light_radiance(Q.light, vec3(Q.grid_to_world * vec4(q, 1.0f)), vx_prop_r_min(), wi, dist);
    if (Q.per_cell_flow != 0) e = vx_radiance_add(vec3(0.0f), e * vx_prop_distance2(q));
    return Q.channels == 1 ? vec3(vx_radiance_add(0.0f, vx_luminance(e)), 0.0f, 0.0f) : e;
}

// Whether slice s lies in the grid along the sweep's axis (-1 and dims: the virtual slices around it).
VX_INLINE bool vx_prop_slice_inside(int s) { return s >= 0 && s < Q.dims[Q.axis]; }

// Whether slice s's centre plane lies past the light's plane, in the sweep's direction (a point or
// spot light's sweep, Q.source its position).
VX_INLINE bool vx_prop_past_light(int s) { return float(Q.direction) * (float(s) + 0.5f - Q.source[Q.axis]) > 0.0f; }

// Where channel ch of cell (i, j) of the previous slice is (vx_prop_prev: Q.channels floats per
// cell, rows of u).
VX_INLINE int vx_prop_prev_index(int axis, int i, int j, int ch) { return (j * Q.dims[vx_axis_u(axis)] + i) * Q.channels + ch; }

// The previous slice's value at cell (i, j) of the slice; `prev` is that slice's index (-1: the
// virtual slice before the grid, all outside).
VX_INLINE vec3 vx_prop_prev_cell(int i, int j, int prev) {
    int u = vx_axis_u(Q.axis);
    int v = vx_axis_v(Q.axis);
    if (!vx_prop_slice_inside(prev) || i < 0 || j < 0 || i >= Q.dims[u] || j >= Q.dims[v])
        return vx_prop_outside(vx_prop_point(Q.axis, float(prev) + 0.5f, float(i) + 0.5f, float(j) + 0.5f));
    int at = vx_prop_prev_index(Q.axis, i, j, 0);
    if (Q.channels == 1) return vec3(vx_prop_prev(at), 0.0f, 0.0f);
    return vec3(vx_prop_prev(at), vx_prop_prev(at + 1), vx_prop_prev(at + 2));
}

// Bilinear read of the previous slice at in-slice coordinates (a, b).
VX_INLINE vec3 vx_prop_prev_at(float a, float b, int prev) {
    float ga = a - 0.5f;
    float gb = b - 0.5f;
    float fa = floor(ga);
    float fb = floor(gb);
    int i = int(fa);
    int j = int(fb);
    float ta = ga - fa;
    float tb = gb - fb;
    return VX_BILERP(vx_prop_prev_cell(i, j, prev), vx_prop_prev_cell(i + 1, j, prev), vx_prop_prev_cell(i, j + 1, prev),
                     vx_prop_prev_cell(i + 1, j + 1, prev), ta, tb);
}

// Grid point of cell (i, j) of slice Q.slice.
VX_INLINE vec3 vx_prop_cell_point(int axis, int i, int j) {
    return vx_prop_point(axis, float(Q.slice) + 0.5f, float(i) + 0.5f, float(j) + 0.5f);
}

// A point or spot light's flow through grid point x (a light exactly at x flows along +z).
VX_INLINE vec3 vx_prop_light_flow(vec3 x) {
    vec3 f = x - Q.source;
    bool at_light = f.x == 0.0f && f.y == 0.0f && f.z == 0.0f;
    return at_light ? vec3(0.0f, 0.0f, 1e-6f) : f;
}

// What a point or spot light's sweep adds of its value at grid point x: its weight times the share
// of the flow through x that this sweep carries (`blend`: Q.blend_axes), so that a light inside or
// beside the volume lights each cell from the sweeps facing it, and over vx_prop_distance2, back
// to radiance.
VX_INLINE float vx_prop_point_weight(int axis, vec3 x, bool blend) {
    return Q.weight * vx_sweep_weight(vx_prop_light_flow(x), axis, Q.direction, blend) / vx_prop_distance2(x);
}

// What cell (i, j) adds of its value: the sweep's weight, or a point or spot light's
// (Q.per_cell_flow) at the cell.
VX_INLINE float vx_prop_weight(int i, int j) {
    if (Q.per_cell_flow == 0) return Q.weight;
    return vx_prop_point_weight(Q.axis, vx_prop_cell_point(Q.axis, i, j), Q.blend_axes != 0);
}

// Whether a point or spot light's sweep leaves a cell whose flow is f dark: one before the light's
// plane, or too far sideways (Q.max_slope) for any cell this sweep weights to read. (Slope from
// one slice behind the light: the first slice past it may be much closer than a cell, and its
// steep neighbours are read by the next slice.)
VX_INLINE bool vx_prop_unlit(int axis, vec3 f) {
    return float(Q.direction) * f[axis] <= 0.0f ||
           max(abs(f[vx_axis_u(axis)]), abs(f[vx_axis_v(axis)])) > float(Q.max_slope) * (abs(f[axis]) + 1.0f);
}

// What a light sweep adds to channel `ch` of a cell of the volume, `value` being what it carries
// there in that channel (a direct sweep's one luminance, for every channel): its weight (the
// cell's vx_prop_weight) times its tint times the value. The GPU's cells and the CPU's rows add
// it alike (vx_radiance_add); the eye sweep's (weight 1) replaces the cell's light instead.
VX_INLINE float vx_prop_added(float weight, int ch, float value) { return (weight * Q.tint[ch]) * value; }

// The step from grid point x back to where its light comes from in the previous slice: the
// direction light flows through x, in grid units, scaled to advance one slice.
// (Both flows are computed and selected component by component: a vector's copy or a conditional
// load would keep the CPU's row batches from vectorising.)
VX_INLINE vec3 vx_prop_back(int axis, vec3 x) {
    bool positional = Q.source_is_position != 0;
    vec3 away = (x - Q.source) * Q.flow;
    vec3 flow = vec3(positional ? away.x : Q.source.x, positional ? away.y : Q.source.y, positional ? away.z : Q.source.z);
    return flow / max(abs(flow[axis]), 1e-6f);
}

// The pieces of the composite trapezoid over a step `back`: one per cell it moves sideways (a
// step of the second blend axis can cross many cells, and the medium's edge, within one slice;
// one of the principal axis moves at most one cell sideways: the plain trapezoid).
VX_INLINE int vx_prop_pieces(int axis, vec3 back) {
    return max(int(ceil(max(abs(back[vx_axis_u(axis)]), abs(back[vx_axis_v(axis)])) - 1e-3f)), 1);
}

// The composite trapezoid's inner point k of `pieces` along the step `back` from p.
VX_INLINE vec3 vx_prop_piece_point(vec3 p, vec3 back, int k, int pieces) { return p + back * (float(k) / float(pieces)); }

// World length of a step `back`.
VX_INLINE float vx_prop_step_world(vec3 back) { return length(mat3(Q.grid_to_world) * back); }

// Radius of the blur disc at the end of a step `back`: its length times tan(half-angle).
VX_INLINE float vx_prop_blur_radius(vec3 back) { return length(back) * Q.blur_tan; }

// The composite trapezoid's integral from its samples' `sum` (the ends halved) over a step of
// world length `step_world` cut into `pieces`.
VX_INLINE float vx_prop_trapezoid(float sum, float step_world, int pieces) { return sum * step_world / float(pieces); }

// The ends of a step from p, on the previous slice's centre plane, to cell (i, j) of slice Q.slice,
// unperturbed: the cell's extinction plus the previous slice's, bilinear at p.
VX_INLINE float vx_prop_exact_ends(int axis, int i, int j, vec3 p, int plane) {
    return vx_prop_sigma_cell(vx_prop_cell_at(axis, Q.slice, i, j), plane) + vx_prop_sigma_slice(axis, p[vx_axis_u(axis)], p[vx_axis_v(axis)], Q.slice - Q.direction, plane);
}

// The step's integral of one plane of the extinction from p to cell (i, j) of slice Q.slice at
// grid point x: a composite trapezoid over `pieces`, times the step's world length. `exact_ends`:
// x is the cell's centre and p lies on the previous slice's centre plane (no perturbation, not a
// light's first slice), so the ends read the cell and a bilinear blend of the slice.
float vx_prop_step_depth(int i, int j, vec3 x, vec3 p, vec3 back, vec4 nx, bool exact_ends, int plane) {
    int axis = Q.axis;
    int pieces = vx_prop_pieces(axis, back);
    float sum = 0.5f * (exact_ends ? vx_prop_exact_ends(axis, i, j, p, plane)
                                   : vx_prop_extinction(x, nx, plane) + vx_prop_extinction(p, vx_prop_noise(p), plane));
    for (int k = 1; k < pieces; ++k) {
        vec3 q = vx_prop_piece_point(p, back, k, pieces);
        sum += vx_prop_extinction(q, vx_prop_noise(q), plane);
    }
    return vx_prop_trapezoid(sum, vx_prop_step_world(back), pieces);
}

// The value of cell (i, j) of slice Q.slice.
VX_INLINE vec3 vx_prop_cell(int i, int j) {
    int axis = Q.axis;
    int u = vx_axis_u(axis);
    int v = vx_axis_v(axis);
    int s = Q.slice;
    int prev = s - Q.direction;
    vec3 x = vx_prop_cell_point(axis, i, j);
    vec3 back = vx_prop_back(axis, x);
    vec3 p = x - back;
    // A point or spot light's sweep starts at the light's own plane (Sunden 2015, Fig. 5): cells
    // before it, and cells too far sideways for any cell this sweep weights to read, stay dark;
    // the first slice past the plane takes the light straight from its source.
    bool first = false;
    if (Q.per_cell_flow != 0) {
        vec3 f = vx_prop_light_flow(x);
        if (vx_prop_unlit(axis, f)) return vec3(0.0f);
        first = !vx_prop_past_light(prev);
        if (first) {
            back = f;
            p = Q.source;
        }
    }
    float step_world = vx_prop_step_world(back);

    // The optical depth of the step.
    vec4 nx = vx_prop_noise(x);
    bool exact_ends = !vx_perturbed() && !first;
    float tau = vx_prop_step_depth(i, j, x, p, back, nx, exact_ends, 0);

    // Transmittance of the step per channel (for indirect light the transport colour's e^-atten,
    // which the noise tints: Kniss Eq. 8 and Sec. III.D). Per material, the step's colour is the
    // extinction-weighted mean of -ln(transport) along it, which is exact where one material
    // fills the step and keeps the optical depth of each channel exact where several do.
    vec3 k = Q.atten;
    if (Q.transport_planes != 0) {
        vec3 depth = vec3(vx_prop_step_depth(i, j, x, p, back, nx, exact_ends, 1), vx_prop_step_depth(i, j, x, p, back, nx, exact_ends, 2),
                          vx_prop_step_depth(i, j, x, p, back, nx, exact_ends, 3));
        k = tau > 0.0f ? depth / tau : vec3(0.0f);
    }
    if (Q.channels == 3 && vx_perturbed() && P.noise_transport != 0.0f)
        k = -log(vx_perturb_transport(exp(-k), nx));
    vec3 transmitted = vec3(vx_exp(-k.x * tau), vx_exp(-k.y * tau), vx_exp(-k.z * tau));
    if (first) return vx_prop_outside(x) * transmitted;
    // Blur: taps on a disc around p in the previous slice, radius = step length * tan(half-angle).
    float radius = vx_prop_blur_radius(back);
    vec3 incoming = vec3(0.0f);
    for (int t = 0; t < Q.tap_count; ++t)
        incoming = vx_radiance_add(incoming, Q.taps[t].weight * vx_prop_prev_at(p[u] + radius * Q.taps[t].offset.x, p[v] + radius * Q.taps[t].offset.y, prev));

    if (Q.eye_sweep != 0) {
        // Eye sweep (Ropinski Sec. 4.1, last paragraphs): the cell keeps its own indirect light in
        // proportion to its opacity and passes on the light from behind it for the rest.
        float alpha = 1.0f - vx_exp(-tau);
        return vx_radiance_add(alpha * vx_prop_outside(x), (1.0f - alpha) * incoming);
    }
    if (Q.source_sweep != 0) {
        // The cell's source q (per world unit) held constant over the step: it adds
        // q * (1 - e^-k tau) / k, the march's emission integral.
        int at = 3 * vx_prop_index(ivec3(floor(x)));
        vec3 q = vec3(vx_prop_in(at), vx_prop_in(at + 1), vx_prop_in(at + 2));
        vec3 kt = k * tau;
        vec3 kept = vec3(vx_exp_integral(kt.x), vx_exp_integral(kt.y), vx_exp_integral(kt.z));
        return vx_radiance_add(incoming * transmitted, q * (kept * step_world));
    }
    return incoming * transmitted;
}

// The CPU's batch of vx_prop_cell for a point or spot light's sweep: a run of cells (i0 + l, j),
// l < n <= VX_PROP_RUN, of slice Q.slice, of an unperturbed sweep (Q.per_cell_flow) without axis
// blending or per-material transport, on a slice past the first beyond the light's plane. Each
// cell steps back along its own ray from the light, so its reads land at offsets of its own
// (gathers), but every lane goes through vx_prop_cell's arithmetic, stage by stage in SIMD: its
// step and the ends of its trapezoid (vx_prop_flow_lane), the inner points (vx_prop_flow_piece),
// the blur taps (vx_prop_flow_tap), the step's transmittance (vx_prop_flow_transmit), leaving its
// value in `incoming`. A lane whose step moves more
// than VX_PROP_RUN_PIECES cells sideways, or whose taps read beyond the slice (where vx_prop_cell
// reads the light itself), is left VX_LANE_REDO for the caller to run vx_prop_cell. The caller
// passes `axis` as a constant (one call per axis), so that these inline without selects.
#define VX_PROP_RUN 256
#define VX_PROP_RUN_PIECES 4     // the default cone's sweeps reach slope 4 (Q.max_slope)
#define VX_LANE_ON 0             // the run's value is the lane's
#define VX_LANE_DARK 1           // no light reaches the cell (vx_prop_cell's early 0)
#define VX_LANE_REDO 2           // the caller runs vx_prop_cell for it

struct VxPropRun {
    float pu[VX_PROP_RUN];       // where the cell's step starts, in the previous slice
    float pv[VX_PROP_RUN];
    float radius[VX_PROP_RUN];   // of its blur disc
    float depth[VX_PROP_RUN];    // its trapezoid's sum of extinction samples
    float step_world[VX_PROP_RUN];
    float weight[VX_PROP_RUN];   // vx_prop_weight
    int pieces[VX_PROP_RUN];
    int state[VX_PROP_RUN];      // VX_LANE_*
    float incoming[3 * VX_PROP_RUN];   // channel-major: the blur taps' sum, then the cell's value
};

VX_INLINE void vx_prop_flow_lane(int axis, int i0, int j, int l, VX_INOUT(VxPropRun) r) {
    vec3 x = vx_prop_cell_point(axis, i0 + l, j);
    vec3 back = vx_prop_back(axis, x);
    vec3 p = x - back;
    int pieces = vx_prop_pieces(axis, back);
    r.pu[l] = p[vx_axis_u(axis)];
    r.pv[l] = p[vx_axis_v(axis)];
    r.radius[l] = vx_prop_blur_radius(back);
    r.depth[l] = 0.5f * vx_prop_exact_ends(axis, i0 + l, j, p, 0);
    r.step_world[l] = vx_prop_step_world(back);
    r.weight[l] = vx_prop_point_weight(axis, x, false);
    r.pieces[l] = pieces;
    r.state[l] = vx_prop_unlit(axis, vx_prop_light_flow(x)) ? VX_LANE_DARK : (pieces <= VX_PROP_RUN_PIECES ? VX_LANE_ON : VX_LANE_REDO);
}

// Inner point k of the lane's trapezoid, added if its step has that many.
VX_INLINE void vx_prop_flow_piece(int axis, int i0, int j, int k, int l, VX_INOUT(VxPropRun) r) {
    vec3 x = vx_prop_cell_point(axis, i0 + l, j);
    vec3 back = vx_prop_back(axis, x);
    float inner = vx_prop_sigma_at(vx_prop_piece_point(x - back, back, k, r.pieces[l]), 0);
    r.depth[l] += k < r.pieces[l] ? inner : 0.0f;
}

// Tap t of the lane's blur disc in channel ch: a bilinear read of the previous slice, as
// vx_prop_prev_at reads it where all four corners lie in the slice (else the lane is redone).
// (Outside, the slice's first cells are read and dropped; the slice has at least 2 x 2 cells.)
VX_INLINE void vx_prop_flow_tap(int axis, int t, int ch, int l, VX_INOUT(VxPropRun) r) {
    int nu = Q.dims[vx_axis_u(axis)];
    int nv = Q.dims[vx_axis_v(axis)];
    float ga = r.pu[l] + r.radius[l] * Q.taps[t].offset.x - 0.5f;
    float gb = r.pv[l] + r.radius[l] * Q.taps[t].offset.y - 0.5f;
    float fa = floor(ga);
    float fb = floor(gb);
    int ia = int(fa);
    int ib = int(fb);
    bool inside = ia >= 0 && ib >= 0 && ia + 1 < nu && ib + 1 < nv;
    r.state[l] = !inside && r.state[l] == VX_LANE_ON ? VX_LANE_REDO : r.state[l];
    int at = inside ? vx_prop_prev_index(axis, ia, ib, ch) : 0;
    int row = nu * Q.channels;
    float value = VX_BILERP(vx_prop_prev(at), vx_prop_prev(at + Q.channels), vx_prop_prev(at + row),
                            vx_prop_prev(at + row + Q.channels), ga - fa, gb - fb);
    r.incoming[ch * VX_PROP_RUN + l] = vx_radiance_add(r.incoming[ch * VX_PROP_RUN + l], Q.taps[t].weight * value);
}

// The lane's value in channel ch, in place of what its taps took in: that times the step's
// transmittance, with `atten` the channel's Q.atten.
VX_INLINE void vx_prop_flow_transmit(int ch, float atten, int l, VX_INOUT(VxPropRun) r) {
    float tau = vx_prop_trapezoid(r.depth[l], r.step_world[l], r.pieces[l]);
    float value = r.incoming[ch * VX_PROP_RUN + l] * vx_exp(-atten * tau);
    r.incoming[ch * VX_PROP_RUN + l] = r.state[l] == VX_LANE_DARK ? 0.0f : value;
}

// Whether the rows of slice Q.slice batch, `prev` the previous slice: the sweep is one the batch
// stands in for, and both slices lie past the light's plane. (The slice has at least 2 x 2 cells:
// a lane reading beyond it reads its first cells instead, and drops them.)
VX_INLINE bool vx_prop_flow_batches(int prev) {
    int axis = Q.axis;
    return Q.per_cell_flow != 0 && Q.eye_sweep == 0 && Q.source_sweep == 0 && Q.blend_axes == 0 && Q.transport_planes == 0 &&
           !vx_perturbed() && Q.strides[vx_axis_u(axis)] == 1 && Q.dims[vx_axis_u(axis)] >= 2 && Q.dims[vx_axis_v(axis)] >= 2 &&
           vx_prop_slice_inside(prev) && vx_prop_past_light(Q.slice) && vx_prop_past_light(prev);
}

VX_INLINE void vx_prop_flow_run(int axis, int i0, int j, int n, VX_INOUT(VxPropRun) r) {
    VX_SIMD_LOOP
    for (int l = 0; l < n; ++l) vx_prop_flow_lane(axis, i0, j, l, r);
    // The inner points, as far as the run's longest step needs (a light far away needs none).
    int most = 1;
    for (int l = 0; l < n; ++l) most = max(most, r.state[l] == VX_LANE_ON ? r.pieces[l] : 1);
    for (int k = 1; k < most; ++k) {
        VX_SIMD_LOOP
        for (int l = 0; l < n; ++l) vx_prop_flow_piece(axis, i0, j, k, l, r);
    }
    for (int ch = 0; ch < Q.channels; ++ch) {
        VX_SIMD_LOOP
        for (int l = 0; l < n; ++l) r.incoming[ch * VX_PROP_RUN + l] = 0.0f;
        for (int t = 0; t < Q.tap_count; ++t) {
            VX_SIMD_LOOP
            for (int l = 0; l < n; ++l) vx_prop_flow_tap(axis, t, ch, l, r);
        }
        float atten = Q.atten[ch];
        VX_SIMD_LOOP
        for (int l = 0; l < n; ++l) vx_prop_flow_transmit(ch, atten, l, r);
    }
}

// The CPU's batch of vx_prop_cell for a sweep whose every cell steps back alike: a directional
// light (or a source sweep along an axis), unperturbed, stepping at most VX_PROP_MAX_SLOPE cells
// sideways. Every cell of a row then reads the previous slice (and, for a step's inner points, its
// own slice) at the same offsets, so a row is a weighted sum of shifted slice rows, SIMD loops
// over contiguous floats: the composite trapezoid's samples (VxPropRead, bilinear blends of the
// two slices) and the blur taps, whose bilinear corner weights add into one stencil (9 taps of 4
// corners fall on 9-16 cells for the default cone's blur radii: one multiply-add per stencil cell
// instead of a blend per tap). These regroup vx_prop_cell's sums, so the two agree to float
// rounding, not bit for bit. The cells of a row whose reads would leave the slice, outside
// [lo, hi), run vx_prop_cell.
#define VX_PROP_MAX_READS 17                    // trapezoid samples: a step VX_PROP_MAX_SLOPE cells sideways
#define VX_PROP_MAX_STENCIL (4 * VX_MAX_TAPS)

// A read at in-slice offset (di + ta, dj + tb) from a cell, bilinear, weighted by w; for a
// trapezoid sample, a blend of the previous slice (slice 0) and the cell's own (1).
struct VxPropRead {
    int di;
    int dj;
    float ta;
    float tb;
    float w;
    float slice;
};

struct VxPropStencil {
    int reads;                                  // 0: the sweep does not batch
    VxPropRead read[VX_PROP_MAX_READS];
    int cells;
    int cell_di[VX_PROP_MAX_STENCIL];
    int cell_dj[VX_PROP_MAX_STENCIL];
    float cell_w[VX_PROP_MAX_STENCIL];          // the taps' summed corner weights there
    int lo;                                     // cells [lo, hi) of a row read inside the slice
    int hi;
    float step_world;
};

VX_INLINE VxPropRead vx_prop_read(float du, float dv, float w, float slice) {
    VxPropRead r;
    float fa = floor(du);
    float fb = floor(dv);
    r.di = int(fa);
    r.dj = int(fb);
    r.ta = du - fa;
    r.tb = dv - fb;
    r.w = w;
    r.slice = slice;
    return r;
}

// Adds weight w at stencil cell (di, dj); the sum is kept in double until it is stored.
void vx_prop_stencil_add(VX_INOUT(VxPropStencil) s, int di, int dj, double w) {
    if (w == 0.0) return;
    for (int c = 0; c < s.cells; ++c)
        if (s.cell_di[c] == di && s.cell_dj[c] == dj) {
            s.cell_w[c] = float(double(s.cell_w[c]) + w);
            return;
        }
    VX_CHECK_INDEX(s.cells, VX_PROP_MAX_STENCIL, "propagation stencil cell");
    s.cell_di[s.cells] = di;
    s.cell_dj[s.cells] = dj;
    s.cell_w[s.cells] = float(w);
    s.cells += 1;
}

// Narrows [lo, hi) to the cells whose read r stays inside a row of nu cells.
void vx_prop_stencil_narrow(VX_INOUT(VxPropStencil) s, int di, int nu) {
    s.lo = max(s.lo, -di);
    s.hi = min(s.hi, nu - 1 - di);
}

// The stencil of sweep Q. reads = 0 (and only reads, cells, lo and hi are set) when its cells do
// not step alike, step further than VX_PROP_MAX_READS samples reach, or its rows are not
// contiguous (Q.strides along u).
void vx_prop_row_stencil(VX_OUT(VxPropStencil) s) {
    int axis = Q.axis;
    int u = vx_axis_u(axis);
    int v = vx_axis_v(axis);
    int nu = Q.dims[u];
    s.reads = 0;
    s.cells = 0;
    s.lo = 0;
    s.hi = nu;
    vec3 back = vx_prop_back(axis, vec3(0.0f));   // the same for every cell
    int pieces = vx_prop_pieces(axis, back);
    if (Q.source_is_position != 0 || Q.eye_sweep != 0 || vx_perturbed() || Q.strides[u] != 1 || pieces + 1 > VX_PROP_MAX_READS)
        return;
    s.step_world = vx_prop_step_world(back);
    // The trapezoid's samples: at fraction f of the step from p (previous slice) to the cell, a
    // blend of the two slices' bilinear reads.
    for (int q = 0; q <= pieces; ++q) {
        float f = float(q) / float(pieces);
        float w = (q == 0 || q == pieces ? 0.5f : 1.0f) * s.step_world / float(pieces);
        s.read[q] = vx_prop_read(-back[u] * (1.0f - f), -back[v] * (1.0f - f), w, f);
        vx_prop_stencil_narrow(s, s.read[q].di, nu);
    }
    s.reads = pieces + 1;
    float radius = vx_prop_blur_radius(back);
    for (int t = 0; t < Q.tap_count; ++t) {
        VxPropRead r = vx_prop_read(-back[u] + radius * Q.taps[t].offset.x, -back[v] + radius * Q.taps[t].offset.y,
                                    Q.taps[t].weight, 0.0f);
        vx_prop_stencil_narrow(s, r.di, nu);
        for (int q = 0; q < 4; ++q) {
            double wu = (q & 1) != 0 ? double(r.ta) : 1.0 - double(r.ta);
            double wv = (q & 2) != 0 ? double(r.tb) : 1.0 - double(r.tb);
            vx_prop_stencil_add(s, r.di + (q & 1), r.dj + (q >> 1), wu * wv * double(r.w));
        }
    }
}

// Whether row j batches, `prev` the previous slice: the sweep has a stencil, `prev` lies in the
// grid, and the row's reads stay inside the slice (rows dj and dj + 1 of every read).
VX_INLINE bool vx_prop_row_fits(VX_IN(VxPropStencil) s, int j, int prev) {
    int nv = Q.dims[vx_axis_v(Q.axis)];
    bool fits = s.reads > 0 && s.lo < s.hi && vx_prop_slice_inside(prev);
    for (int k = 0; k < s.reads; ++k) fits = fits && j + s.read[k].dj >= 0 && j + s.read[k].dj + 1 < nv;
    for (int c = 0; c < s.cells; ++c) fits = fits && j + s.cell_dj[c] >= 0 && j + s.cell_dj[c] < nv;
    return fits;
}

struct VxPropRowRun {
    float tau[4 * VX_PROP_RUN];     // plane-major: the step's optical depth (plane 0), or with
                                    // per-material transport each channel's (planes 1-3)
    float light[3 * VX_PROP_RUN];   // interleaved as the slice: the taps' sum, then the cells' values
};

// Cells [base, base + n) of row j (n <= VX_PROP_RUN, inside [s.lo, s.hi)), `prev` the previous
// slice, into r.light: vx_prop_cell's value, Q.channels floats per cell.
VX_INLINE void vx_prop_row_run(VX_IN(VxPropStencil) s, int j, int prev, int base, int n, VX_INOUT(VxPropRowRun) r) {
    int axis = Q.axis;
    int sv = Q.strides[vx_axis_v(axis)];
    int sa = Q.strides[axis];
    int nu = Q.dims[vx_axis_u(axis)];
    int channels = Q.channels;
    int plane_cells = Q.dims.x * Q.dims.y * Q.dims.z;
    int planes = Q.transport_planes != 0 ? 4 : 1;
    for (int plane = planes > 1 ? 1 : 0; plane < planes; ++plane) {
        int at_tau = plane * VX_PROP_RUN;
        VX_SIMD_LOOP
        for (int q = 0; q < n; ++q) r.tau[at_tau + q] = 0.0f;
        for (int k = 0; k < s.reads; ++k) {
            // (Index arithmetic from the strides, not vx_prop_sigma_index: built from a cell with a
            // run-time axis, the directional sweeps took 5-10% longer in two runs of
            // voxlux_bench_propagation --paper-only.)
            int row_prev = plane * plane_cells + prev * sa + (j + s.read[k].dj) * sv + base + s.read[k].di;
            int row_here = plane * plane_cells + Q.slice * sa + (j + s.read[k].dj) * sv + base + s.read[k].di;
            float ta = s.read[k].ta;
            float tb = s.read[k].tb;
            float f = s.read[k].slice;
            float w = s.read[k].w;
            VX_SIMD_LOOP
            for (int q = 0; q < n; ++q) {
                float in_prev = VX_BILERP(vx_prop_sigma(row_prev + q), vx_prop_sigma(row_prev + q + 1), vx_prop_sigma(row_prev + q + sv),
                                          vx_prop_sigma(row_prev + q + sv + 1), ta, tb);
                float in_here = VX_BILERP(vx_prop_sigma(row_here + q), vx_prop_sigma(row_here + q + 1), vx_prop_sigma(row_here + q + sv),
                                          vx_prop_sigma(row_here + q + sv + 1), ta, tb);
                r.tau[at_tau + q] += w * mix(in_prev, in_here, f);
            }
        }
    }
    // The blur taps, as their stencil. A cell reads every channel at the same offsets with the
    // same weights, so on the interleaved slice a run of n cells is n * channels contiguous floats.
    int floats = n * channels;
    VX_SIMD_LOOP
    for (int m = 0; m < floats; ++m) r.light[m] = 0.0f;
    for (int c = 0; c < s.cells; ++c) {
        int at = ((j + s.cell_dj[c]) * nu + base + s.cell_di[c]) * channels;
        float w = s.cell_w[c];
        VX_SIMD_LOOP
        for (int m = 0; m < floats; ++m) r.light[m] = vx_radiance_add(r.light[m], w * vx_prop_prev(at + m));
    }
    // Each channel times its transmittance over the step (its own plane's optical depth, or tau
    // times the medium's k); a source sweep adds the cell's own source over the step.
    int source_row = (Q.slice * sa + j * sv + base) * 3;
    float step_len = s.step_world;
    for (int ch = 0; ch < channels; ++ch) {
        float kc = Q.atten[ch];
        int at_tau = planes > 1 ? (ch + 1) * VX_PROP_RUN : 0;
        float scale = planes > 1 ? 1.0f : kc;
        if (Q.source_sweep == 0) {
            VX_SIMD_LOOP
            for (int q = 0; q < n; ++q) r.light[q * channels + ch] *= vx_exp(-(scale * r.tau[at_tau + q]));
        } else {
            VX_SIMD_LOOP
            for (int q = 0; q < n; ++q) {
                float kt = scale * r.tau[at_tau + q];
                r.light[q * channels + ch] = vx_radiance_add(r.light[q * channels + ch] * vx_exp(-kt),
                                                             vx_prop_in(source_row + q * 3 + ch) * (step_len * vx_exp_integral(kt)));
            }
        }
    }
}
