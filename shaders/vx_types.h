// Plain data shared by both backends. Every member is a vec4/ivec4/mat4 so that the std430
// layout of the GL buffers and the C++ struct layout are the same bytes.
#pragma once
#include "vx_prelude.h"

// One light. pos_type: xyz world position (point/spot), w = VX_LIGHT_*.
// dir_cos: xyz unit world direction the light travels (directional/spot),
//          w = cos(outer cone half-angle) for spots.
// color: rgb = colour * intensity (scene-linear, unclamped), w = cos(inner half-angle) for spots.
struct VxLight {
    vec4 pos_type;
    vec4 dir_cos;
    vec4 color;
};

// Everything the march needs besides the data arrays.
struct VxParams {
    mat4 camera_to_world;   // camera looks down -Z, +Y up
    mat4 world_to_index;    // affine inverse of the grid's index-to-world transform
    vec4 camera_frame;      // x = tan(fov_y / 2), y = aspect (w / h), z = width, w = height
    vec4 march;             // x = step (world units), y = shadow step (world units),
                            // z = transmittance cutoff, w = HG anisotropy g
    vec4 material;          // rgb = albedo, w = density (extinction) scale
    ivec4 emission_map;     // x = emission sources (0 = none), y = atlas floats per source channel
    vec4 emission_domain;   // per source (component s): 1 / the largest value of its grid in this frame
                            // (0: it emits nowhere), mapping grid values onto its table
    vec4 tf_domain;         // x = value at LUT entry 0, y = 1 / (value range), z = 1 if the LUT is used,
                            // w = 1 if a colour (Cd) grid is bound
    ivec4 bricks_min;       // xyz = lowest occupied brick coordinate, w = light count
    ivec4 bricks_max;       // xyz = highest occupied brick coordinate, w = shadow mode VX_SHADOWS_*
    ivec4 page;             // x = page-table capacity (power of two), y = max probe length,
                            // z = number of point and spot lights
    vec4 ambient;           // rgb = ambient light radiance (light type "ambient"), w = 1 if any
    mat4 world_to_cache;    // world -> light-cache cell coordinates (cell centres at i + 0.5)
    ivec4 cache_dims;       // xyz = light-cache cells (0 = no cache), w = floats per cell
    ivec4 cache_map;        // x = first ambient-occlusion channel (-1 none), y = 3 if AO is RGB
                            // (colour bleeding) else 1, z = first shadow channel (-1 none)
    // The illumination volume (propagation shadows): direct luminance per cell, then the indirect
    // RGB block, possibly at a coarser (chroma-subsampled) resolution.
    mat4 world_to_illum;    // world -> illumination-volume cell coordinates (cell centres at i + 0.5)
    ivec4 illum_dims;       // xyz = luminance cells (0 = no volume), w = chroma subsampling factor (1 or 2)
    ivec4 chroma_dims;      // xyz = indirect cells, w = first float of the indirect block
    vec4 indirect;          // rgb = transport colour, w = indirect strength / 4pi (0 = no indirect light)
    vec4 surface;           // Kniss Eq. 11: x = gradient where surface shading starts, y = 1 / (gradient
                            // where it is full - x) (0 = off), z = specular weight, w = shininess
    vec4 noise_scale;       // perturbation: x = first-octave noise texels per world unit, y = octaves
                            // (0 = off), z = lacunarity, w = gain
    vec4 noise_offset;      // xyz = world offset of the noise (animation), w = displacement in index voxels
    vec4 noise_amp;         // x = extinction amplitude, y = transport-colour amplitude
};

// The light passes' parameters (Schlegel 2011): the extinction SAT over the light grid and the
// AO-shell and shadow-cone queries that fill the light cache. Light-grid coordinates are cells:
// cell (i, j, k) spans [i, i+1) x [j, j+1) x [k, k+1).
struct VxSatParams {
    mat4 light_to_world;    // light-grid coordinates -> world
    mat4 world_to_light;
    ivec4 dims;             // xyz = light-grid cells, w = SAT planes (1 extinction, 4 with bleeding)
    vec4 quantum;           // per SAT plane: the value of one integer unit (a power of two)
    vec4 shells;            // x = shell count, y = neighbourhood radius in cells,
                            // z = world edge of one cell, w = SAT plane the AO pass reads
    vec4 cone;              // x = tan(cone half-angle), y = cuboids per cone, z = growth,
                            // w = (1 + growth)^cuboids
    ivec4 pass;             // x = light index (shadow pass), y = cache channel written,
                            // z = floats per cache cell, w = unused
};

// One propagation sweep (Ropinski 2010, Sec. 4.1) over a grid of cells, slice by slice along an
// axis. A light sweep carries one light through the grid (1 channel: direct luminance, unblurred;
// 3: indirect RGB, blurred in a cone) and adds it, tinted and weighted, to the RGB block of the
// illumination volume; the eye sweep carries the indirect light towards the camera. Grid
// coordinates are cells: cell (i, j, k) spans [i, i+1) x [j, j+1) x [k, k+1).
#define VX_MAX_TAPS 32
// The second blend axis fades out before its steps move this many cells sideways per slice.
#define VX_PROP_MAX_SLOPE 16.0f
struct VxPropParams {
    mat4 grid_to_world;
    mat4 world_to_grid;
    ivec4 dims;             // xyz = cells, w = channels propagated (1 or 3)
    ivec4 slice;            // x = axis, y = +1 / -1 (the way slices advance), z = slice written, w = blur taps
    ivec4 strides;          // xyz = index step per cell along x, y, z of the extinction grid and eye input
    ivec4 mode;             // x = 1: weight each cell by its own flow (point and spot lights),
                            // y = 1: blend the two closest axes (Sunden 2015, Eq. 5), z = the
                            // steepest slope (cells sideways per slice) a point sweep computes, w = unused
    vec4 source;            // xyz = grid position of the light (or camera), or for a directional light the
                            // grid-space direction it travels; w = 1 for a position, 0 for a direction
    vec4 flow;              // x = +1 light sweep (flow away from the source), -1 eye sweep (towards it);
                            // y = tan(blur cone half-angle), z = weight this sweep adds (negative:
                            // subtracts), w = 1 for the eye sweep
    vec4 atten;             // xyz = optical-depth multiplier per channel (1 direct, -ln(transport) indirect),
                            // w = grid cells per index voxel (the perturbation's displacement is in voxels)
    vec4 tint;              // xyz = RGB added per unit propagated (direct: the light's colour over its
                            // luminance; indirect and eye: 1), w = unused
    VxLight light;          // the light (world), for the radiance that enters from outside the grid
    vec4 taps[VX_MAX_TAPS]; // xy = offset in the unit disc, z = weight (the weights sum to 1)
};

// What one camera ray returns; the AOVs are kept separate so the EXR writer can lay them out.
struct VxPixel {
    vec4 rgba;              // premultiplied scene-linear radiance, alpha = 1 - transmittance
    vec3 direct;            // single-scattered light from the scene lights
    vec3 ambient;           // scattered ambient light (occluded when ambient occlusion is on)
    vec3 emission;          // self-emitted light
    vec3 indirect;          // multiply scattered light (propagation with effects.indirect)
    float transmittance;    // of the whole ray
    float depth;            // camera-space distance, opacity-weighted mean (0 where nothing was hit)
    float samples;          // samples the march evaluated (its cost; the benchmark counts these)
    float variance;         // of the pixel's luminance estimate (Monte Carlo reference); 0 from the march.
                            // 20 floats: whole vec4s
};
