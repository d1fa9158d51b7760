// Plain data shared by both backends: the kernel's parameters, one named member per value, and
// the structs its arrays hold. The GL buffers' std140/std430 layouts and the C++ layouts are the
// same bytes (see the layout rule below).
#pragma once
#include "vx_prelude.h"

// Layout: the structs below are uniform blocks (std140) or storage-buffer arrays (std430) on the
// GL side and plain C++ structs on the CPU side, the same bytes on both. Each line of members
// fills 16 bytes: a mat4, a vec4, four 4-byte scalars, or a vec3/ivec3 and one scalar after it.
// std140 puts a vector, matrix or struct at a multiple of 16 bytes where C++ packs it at 4, so
// kernel_types.h checks that every such member already sits there. Flags are ints (a GLSL bool
// is 4 bytes, a C++ bool 1).

// One light.
struct VxLight {
    vec3 position;          // world (point and spot lights; 0 for directional)
    int type;               // VX_LIGHT_*
    vec3 direction;         // unit world direction the light travels (directional and spot)
    float cos_outer;        // cos(outer cone half-angle) (spot)
    vec3 color;             // colour * intensity (scene-linear, unclamped)
    float cos_inner;        // cos(inner half-angle) (spot)
    int group;              // its light group's index (output.aovs "light_groups"; 0 without them)
    int link_set;           // its link set (light linking, VxVolume.lit_sets; 0 without linking)
    int pad1;
    int pad2;
};

// Everything the march needs besides the data arrays.
struct VxParams {
    mat4 camera_to_world;   // camera looks down -Z, +Y up
    mat4 world_to_index;    // affine inverse of the grid's index-to-world transform (placed)
    mat4 velocity_to_world; // the volume's placement: velocity grids hold the file's world units

    float tan_half_fov;     // tan(vertical field of view / 2)
    float aspect;           // width / height
    int width;              // pixels
    int height;

    float step;             // march step, world units
    float shadow_step;      // ray-marched shadows' step, world units
    float transmittance_cutoff;
    float anisotropy;       // Henyey-Greenstein g

    vec3 albedo;
    float density_scale;    // extinction per unit of the density grid

    ivec3 bricks_min;       // lowest occupied brick coordinate
    int page_capacity;      // page-table entries (a power of two)
    ivec3 bricks_max;       // highest occupied brick coordinate
    int page_max_probe;     // longest probe sequence in the page table

    int light_count;        // lights in the light array (ambient lights are summed into `ambient`)
    int local_light_count;  // of which point and spot lights
    int shadow_rays;        // 1: shadows are brute-force rays through the medium (effects.shadows "raymarch")
    int emission_sources;   // emitting grids (0 = none)

    vec3 ambient;           // ambient light radiance (light type "ambient")
    int has_ambient;        // 1 if any ambient light is on

    vec4 emission_domain;   // per source s (component s): 1 / the largest value of its grid in this
                            // frame (0: it emits nowhere), mapping grid values onto its table

    float transfer_lo;      // grid value at transfer-function LUT entry 0
    float transfer_inv_range;  // 1 / (value range of the LUT)
    int use_transfer;       // 1 if the transfer-function LUT is used
    int use_color_grid;     // 1 if a colour (Cd) grid is bound

    int emission_source_floats;  // atlas floats per emission source
    float surface_low;      // Kniss Eq. 11: gradient where surface shading starts
    float surface_inv_range;  // 1 / (gradient where it is full - surface_low) (0 = off)
    float specular;         // specular weight

    float shininess;
    float displacement;     // perturbation: displacement in index voxels
    float noise_frequency;  // first-octave noise texels per world unit
    int noise_octaves;      // 0 = no perturbation
    vec3 noise_offset;      // world offset of the noise (animation)
    float lacunarity;
    float gain;
    float noise_density;    // extinction amplitude
    float noise_transport;  // transport-colour amplitude
    int voxel_filter;       // VX_FILTER_* (filter is a GLSL reserved word)
    int deep_samples;       // deep samples per ray (output.deep_samples), 0 = no deep output
    int motion_blur;        // 1: camera rays take times within the shutter (vx_motion.h)
    int time_samples;       // rays a pixel spreads over the shutter and the lens (the march; 1 without
                            // motion blur and depth of field)
    int volume_count;       // 0: one volume, the arrays' own; else the volumes of vx_placed_volume (vx_volumes.h)

    int use_velocity;       // 1 if a velocity grid is bound (atlas channel vx_atlas_velocity)
    float velocity_per_frame;  // velocity_scale / fps: world units a frame per unit of the velocity grid
    float shutter_open;     // frames from the frame's own time
    float shutter_close;
    int camera_moves;       // 1: rays move from camera_open to camera_close over the shutter
    int velocity_offset;    // GL: first float of the velocity in its storage block (vx_gl_bindings.glsl)
    int region_capacity;    // entries of the regions' table, after the bricks' in the page entries
    int region_max_probe;   // longest probe sequence in it

    int use_surface_grid;   // 1: a per-voxel surface weight (vx_atlas_surface, Kniss Eq. 11)
                            // scales the gradient ramp's
    int surface_offset;     // GL: its first float in the vectors' block (vx_gl_bindings.glsl)
    int volume_roles;       // 1 if a volume of vx_placed_volume is not visible: alpha is the visible volumes' coverage
    int light_group;        // the light group this march scatters the lights of (VxLight.group; all
                            // lights are group 0 without output.aovs "light_groups")
    int holdout;            // 1: camera rays stop at the depth holdouts' surface (vx_holdout_distance)
    int holdout_offset;     // GL: the holdout depth's first float in the vectors' block (vx_gl_bindings.glsl)
    int link_sets;          // light linking: the link sets of VxLight.link_set (0: every light lights
                            // and is shadowed by every volume)
    float lens_radius;      // depth of field (vx_through_lens): the thin lens's radius, world units; 0: a pinhole

    float focus_distance;   // camera-space depth the lens is sharp at, world units
    int pad8;
    int pad9;
    int pad10;
    mat4 camera_open;       // camera-to-world at shutter open and close (camera.motion)
    mat4 camera_close;
};

// Where one volume's bricks sit in the page entries: its table of capacity entries from `first`
// (vx_brick_hash, linear probing), and the box of its bricks. The one volume of a scene has the
// whole table (vx_own_pages); the volumes of a scene of several share one atlas and one entries
// array, each its own range (src/volume/scene_bricks.h).
struct VxPageRange {
    ivec3 lo;               // lowest stored brick coordinate
    int first;              // its first page entry
    ivec3 hi;               // highest stored brick coordinate
    int capacity;           // its entries (a power of two)
    int max_probe;          // its longest probe sequence
    int pad0;
    int pad1;
    int pad2;
};

// One volume of a scene of several (P.volume_count > 0, shaders/vx_volumes.h): where it sits, what
// it is made of and what it is to the camera. An instance is a volume of its own whose pages are
// another's.
struct VxVolume {
    mat4 world_to_index;    // inverse of its placed index-to-world transform
    VxPageRange pages;
    vec3 albedo;
    float density_scale;    // extinction per world unit per unit of its density grid
    float anisotropy;       // Henyey-Greenstein g
    int role;               // VX_ROLE_*
    int transfer_row;       // its transfer function's first row in the table (-1: it has none)
    int use_color;          // 1 if it has a colour (Cd) grid
    float transfer_lo;      // grid value at its table's first row
    float transfer_inv_range;  // 1 / (value range of its table)
    int color_offset;       // from a tap's index in the density to its colour's (vx_atlas_color)
    int use_velocity;       // 1 if it moves under motion blur (its velocity in its index voxels a second)
    int velocity_offset;    // from a tap's index in the density to its velocity's (vx_atlas_velocity)
    int lit_sets;           // light linking: bit s set when the lights of link set s light it
    int shadow_sets;        // bit s set when its extinction shadows the lights of link set s
    int pad2;
    int emission_first;     // its first emission source: the scene's sources are numbered volume by
                            // volume (P.emission_domain and the emission table's rows)
    int emission_count;     // its sources (0: it emits nothing)
    int emission_offset;    // from a tap's index in the density to its first source's
    int emission_stride;    // atlas floats from one of its sources to the next (its slots' voxels)
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

// One deep sample of a camera ray (shaders/vx_deep.h): a stretch of medium in camera-space depth.
struct VxDeepSample {
    vec3 rgb;               // premultiplied colour, as seen from the sample's front
    float alpha;            // opacity of the stretch
    float z;                // front and back, camera-space depth
    float z_back;
};

// The page table's layout: an open-addressed table with linear probing, whose slot for a brick
// coordinate starts at this hash, so its size follows the number of occupied bricks, never the
// bounding box. The table's builder (src/volume/page_table.cpp) and the kernel's lookup
// (vx_page_lookup) both use it.
VX_INLINE uint vx_brick_hash(ivec3 b) {
    return (uint(b.x) * 73856093u) ^ (uint(b.y) * 19349663u) ^ (uint(b.z) * 83492791u);
}

// The region (the march's coarse level, shaders/vx_dda.h) holding brick `b`: floor(b / 8), as an
// arithmetic shift (GLSL and C++20 both extend the sign; division would round negatives up).
VX_INLINE ivec3 vx_region_of(ivec3 b) {
    return b >> VX_REGION_SHIFT;
}

// PCG hash (Jarzynski and Olano 2020): one well-mixed 32-bit word per input word. The march's
// per-pixel shutter offsets and the reference's random numbers (src/reference/sample_sequence.cpp).
VX_INLINE uint vx_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Radiance sums stop at the largest float rather than overflow to infinity, so HDR lights up to
// 3.4e38 stay finite wherever their light adds up (docs/scene.md, "Extreme values"); the terms
// are never negative, so such a sum is never NaN either.
#define VX_FLOAT_MAX 3.402823466e38f
VX_INLINE float vx_radiance_add(float sum, float term) { return min(sum + term, VX_FLOAT_MAX); }
VX_INLINE vec3 vx_radiance_add(vec3 sum, vec3 term) { return min(sum + term, vec3(VX_FLOAT_MAX)); }
