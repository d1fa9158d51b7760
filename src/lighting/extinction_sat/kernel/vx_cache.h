// The light cache as the march reads it (Extinction-SAT method): optical depths (ambient
// occlusion, per-light shadow) stored at light-grid cell centres, trilinearly interpolated. One
// cell lookup per sample serves every channel; optical depth rather than transmittance is
// interpolated because it is linear in depth inside a homogeneous medium, so the interpolation is
// exact there.
#pragma once
#include "vx_grid.h"
#include "vx_optics.h"

VxGridCell vx_cache_cell(vec3 world) {
    return vx_grid_cell(vec3(P.world_to_cache * vec4(world, 1.0f)), P.cache_dims, P.cache_floats);
}

// Channel `ch` of the cache at a sample.
float vx_cache_value(VxGridCell cell, int ch) {
    VX_CHECK_INDEX(ch, P.cache_floats, "light-cache channel");
    return VX_GRID_TRILINEAR(vx_cache, cell, P.cache_dims, P.cache_floats, ch);
}

// Ambient transmittance at a sample: exp(-tau_AO), per channel with colour bleeding.
vec3 vx_ambient_occlusion(VxGridCell cell) {
    if (P.ao_channel < 0) return vec3(1.0f);
    if (P.ao_channels == 1) return vec3(vx_exp(-vx_cache_value(cell, P.ao_channel)));
    return vec3(vx_exp(-vx_cache_value(cell, P.ao_channel)), vx_exp(-vx_cache_value(cell, P.ao_channel + 1)),
                vx_exp(-vx_cache_value(cell, P.ao_channel + 2)));
}
