// GL entry point of one light pass: one invocation per light-grid cell, the AO-shell or
// shadow-cone query of vx_sat.h for the cells the march can read (Needed), 0 elsewhere.

layout(local_size_x = 64) in;

uniform int vx_cell_offset;   // first cell of this dispatch

layout(std430, binding = VX_BIND_NEEDED) readonly buffer Needed { uint vx_needed[]; };   // one byte per cell
layout(std430, binding = VX_BIND_CHANNEL) writeonly buffer Channel { float vx_channel[]; };

void main() {
    int i = int(gl_GlobalInvocationID.x) + vx_cell_offset;
    if (i >= S.dims.x * S.dims.y * S.dims.z) return;
    if (((vx_needed[i >> 2] >> (8 * (i & 3))) & 255u) == 0u) {
        vx_channel[i] = 0.0f;
        return;
    }
    ivec3 c = ivec3(i % S.dims.x, (i / S.dims.x) % S.dims.y, i / (S.dims.x * S.dims.y));
    vx_channel[i] = S.light < 0 ? vx_ambient_tau(c, S.ao_plane) : vx_cone_tau(c, vx_light(S.light));
}
