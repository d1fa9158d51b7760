// The propagation method's parameter blocks (Ropinski 2010, Sunden 2015), plain data as
// vx_types.h's (its layout rule holds): VxPropParams for one sweep, VxPropagationMarch for the
// march that reads the illumination volume (L.propagation, vx_illumination.h). Registered in
// method.cmake.
#pragma once
#include "vx_types.h"

// One propagation sweep (Ropinski 2010, Sec. 4.1) over a grid of cells, slice by slice along an
// axis. A light sweep carries one light through the grid (1 channel: direct luminance, unblurred;
// 3: indirect RGB, blurred in a cone) and adds it, tinted and weighted, to the RGB block of the
// illumination volume; the eye sweep carries the indirect light towards the camera. Grid
// coordinates are cells: cell (i, j, k) spans [i, i+1) x [j, j+1) x [k, k+1).
#define VX_MAX_TAPS 32
// The second blend axis fades out before its steps move this many cells sideways per slice.
#define VX_PROP_MAX_SLOPE 16.0f

// One blur tap: an offset in the unit disc and its weight (the weights sum to 1).
struct VxTap {
    vec2 offset;
    float weight;
    float pad0;
};

struct VxPropParams {
    mat4 grid_to_world;
    mat4 world_to_grid;
    ivec3 dims;             // cells
    int channels;           // propagated per cell (1 or 3)
    int axis;               // the sweep axis
    int direction;          // +1 / -1: the way slices advance
    int slice;              // the slice written
    int tap_count;          // blur taps
    ivec3 strides;          // index step per cell along x, y, z of the extinction grid and sweep input
    int max_slope;          // the steepest slope (cells sideways per slice) a point sweep computes
    int per_cell_flow;      // 1: weight each cell by its own flow (point and spot lights)
    int blend_axes;         // 1: blend the two closest axes (Sunden 2015, Eq. 5)
    int eye_sweep;          // 1 for the eye sweep (flow towards the camera)
    int source_sweep;       // 1: light enters nowhere from outside, and each cell adds its own source
                            // (vx_prop_in, radiance per world unit: emission, or scattered light)
    vec3 source;            // grid position of the light (or camera), or for a directional light
                            // the grid-space direction it travels
    int source_is_position; // 1 for a position, 0 for a direction
    float flow;             // +1 light sweep (flow away from the source), -1 eye sweep (towards it)
    float blur_tan;         // tan(blur cone half-angle)
    float weight;           // what this sweep adds (negative: subtracts)
    float cells_per_voxel;  // grid cells per index voxel (the perturbation's displacement is in voxels)
    vec3 atten;             // optical-depth multiplier per channel (1 direct, -ln(transport) indirect)
    int transport_planes;   // 1: the indirect sweep's -ln(transport) is per cell, in planes 1-3 of
                            // vx_prop_sigma (extinction times it), and atten is unused
    vec3 tint;              // RGB added per unit propagated (direct: the light's colour over its
                            // luminance; indirect and eye: 1)
    int block_first;        // floats from the pass's RGB block to this sweep's: its light's group's
                            // volume (IlluminationVolume::groups)
    VxLight light;          // the light (world), for the radiance that enters from outside the grid
    VxTap taps[VX_MAX_TAPS];
};

// The illumination volume as the march reads it: direct RGB per cell, then the indirect RGB block,
// possibly at a coarser (chroma-subsampled) resolution; with light groups or light linking, one
// such volume per block (a light group's, of a link set), the march reading its own.
struct VxPropagationMarch {
    mat4 world_to_illum;    // world -> illumination-volume cell coordinates (cell centres at i + 0.5)
    ivec3 illum_dims;       // direct-light cells (0 = no volume)
    int chroma_factor;      // indirect block's subsampling (1 or 2)
    ivec3 chroma_dims;      // indirect-light cells
    int indirect_offset;    // first float of the indirect block
    float indirect_weight;  // indirect strength / 4 pi (0 = no indirect light)
    int light_filter;       // VX_FILTER_*: how the volume is read between cells (effects.propagation.filter;
                            // `filter` is a GLSL reserved word)
    int block_floats;       // floats from one block's volume to the next (a light group's, of a link set: vx_light_block)
    int pad1;
};
