// The light cache as the march reads it (Extinction-SAT method): optical depths (ambient
// occlusion, per-light shadow) stored at light-grid cell centres, trilinearly interpolated. One
// cell lookup per sample serves every channel; optical depth rather than transmittance is
// interpolated because it is linear in depth inside a homogeneous medium, so the interpolation is
// exact there. The method's march hooks (cmake/kernel_contract.cmake) over L.extinction_sat.
// Cost per sample: one cell lookup, then 8 reads per channel read.
#pragma once
#include "vx_grid.h"
#include "vx_optics.h"

struct VxSatSample {
    VxGridCell cell;   // the sample's light-cache cell (unset without a cache)
};

VX_INLINE VxGridCell vx_cache_cell(vec3 world) {
    return vx_grid_cell(vec3(L.extinction_sat.world_to_cache * vec4(world, 1.0f)), L.extinction_sat.cache_dims, L.extinction_sat.cache_floats);
}

// Channel `ch` of the cache at a sample.
VX_INLINE float vx_cache_value(VxGridCell cell, int ch) {
    VX_CHECK_INDEX(ch, L.extinction_sat.cache_floats, "light-cache channel");
    return VX_GRID_TRILINEAR(vx_cache, cell, L.extinction_sat.cache_dims, L.extinction_sat.cache_floats, ch);
}

VX_INLINE bool vx_extinction_sat_varies() { return L.extinction_sat.cache_dims.x > 0; }

VX_INLINE bool vx_extinction_sat_shadows() { return L.extinction_sat.shadows != 0; }

VX_INLINE VxSatSample vx_extinction_sat_sample(vec3 x) {
    VxSatSample s;
    s.cell.base = 0;
    s.cell.fx = 0.0f;
    s.cell.fy = 0.0f;
    s.cell.fz = 0.0f;
    if (vx_extinction_sat_varies()) s.cell = vx_cache_cell(x);
    return s;
}

// Light `light`'s cone transmittance: exp(-tau) of its shadow channel.
VX_INLINE float vx_extinction_sat_shadow(VxSatSample s, int light) {
    if (L.extinction_sat.shadows == 0) return 1.0f;
    return vx_exp(-vx_cache_value(s.cell, L.extinction_sat.shadow_channel + light));
}

// Ambient transmittance at a sample: exp(-tau_AO), per channel with colour bleeding.
VX_INLINE vec3 vx_extinction_sat_ambient(VxSatSample s) {
    int ao = L.extinction_sat.ao_channel;
    if (L.extinction_sat.ao_channels == 0) return vec3(1.0f);
    if (L.extinction_sat.ao_channels == 1) return vec3(vx_exp(-vx_cache_value(s.cell, ao)));
    return vec3(vx_exp(-vx_cache_value(s.cell, ao)), vx_exp(-vx_cache_value(s.cell, ao + 1)), vx_exp(-vx_cache_value(s.cell, ao + 2)));
}
