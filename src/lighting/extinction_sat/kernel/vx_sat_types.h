// The Extinction-SAT method's parameter blocks (Schlegel 2011), plain data as vx_types.h's (its
// layout rule holds): VxSatParams for the light passes that fill the light cache, VxSatMarch for
// the march that reads it (L.extinction_sat, vx_cache.h). Registered in method.cmake.
#pragma once
#include "vx_types.h"

// The light passes' parameters (Schlegel 2011): the extinction SAT over the light grid and the
// AO-shell and shadow-cone queries that fill the light cache. Light-grid coordinates are cells:
// cell (i, j, k) spans [i, i+1) x [j, j+1) x [k, k+1).
struct VxSatParams {
    mat4 light_to_world;    // light-grid coordinates -> world
    mat4 world_to_light;
    ivec3 dims;             // light-grid cells
    int planes;             // SAT planes (1 extinction, 4 with bleeding)
    vec4 quantum;           // per SAT plane: the value of one integer unit (a power of two)
    int shells;             // AO shell count
    float shell_radius;     // AO neighbourhood radius, cells
    float cell_world;       // world edge of one cell
    int ao_plane;           // SAT plane the AO pass reads
    float cone_tan;         // tan(cone half-angle)
    int cone_cuboids;       // cuboids per cone
    float cone_growth;      // each cuboid this much longer than the one before
    float cone_growth_total;  // (1 + growth)^cuboids
    int light;              // light index (shadow pass), -1 for ambient occlusion
    int channel;            // cache channel written
    int cache_floats;       // floats per cache cell
    int pad0;
};

// The light cache as the march reads it: optical depths at the cells of the light grid.
struct VxSatMarch {
    mat4 world_to_cache;    // world -> light-cache cell coordinates (cell centres at i + 0.5)
    ivec3 cache_dims;       // light-cache cells (0 = no cache)
    int cache_floats;       // floats per light-cache cell
    int ao_channel;         // first ambient-occlusion channel
    int ao_channels;        // 0: no ambient occlusion, 1, or 3 with colour bleeding
    int shadow_channel;     // first per-light shadow channel
    int shadows;            // 1: the lights' shadows are read from their channels (effects.shadows "sat_cone")
};
