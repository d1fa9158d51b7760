// GL entry point of one slice of a propagation sweep (vx_propagation.h): one invocation per cell
// of slice Q.slice. The backend dispatches the slices in order, swapping the two slice buffers
// between dispatches; a light sweep adds its light into the volume's RGB block (vx_prop_added),
// the eye sweep replaces the block's light.

layout(local_size_x = 64) in;

layout(std430, binding = VX_BIND_VOLUME) buffer Volume { float vx_volume[]; };   // the pass's RGB blocks (Q.block_first: this sweep's)
layout(std430, binding = VX_BIND_SLICE_OUT) writeonly buffer SliceOut { float vx_slice_out[]; };

void main() {
    int axis = Q.axis;
    int u = vx_axis_u(axis);
    int v = vx_axis_v(axis);
    int n = int(gl_GlobalInvocationID.x);
    if (n >= Q.dims[u] * Q.dims[v]) return;
    int i = n % Q.dims[u];
    int j = n / Q.dims[u];
    vec3 value = vx_prop_cell(i, j);
    for (int ch = 0; ch < Q.channels; ++ch) vx_slice_out[n * Q.channels + ch] = value[ch];
    ivec3 c = vx_prop_cell_at(axis, Q.slice, i, j);
    int cell = Q.block_first + ((c.z * Q.dims.y + c.y) * Q.dims.x + c.x) * 3;
    float weight = Q.eye_sweep != 0 ? 1.0f : vx_prop_weight(i, j);
    for (int ch = 0; ch < 3; ++ch) {
        float added = vx_prop_added(weight, ch, value[Q.channels == 1 ? 0 : ch]);
        vx_volume[cell + ch] = Q.eye_sweep != 0 ? added : vx_radiance_add(vx_volume[cell + ch], added);
    }
}
