// GL entry point of the SAT scan: one invocation per line of SAT entries along vx_scan_axis, a
// running 96-bit sum (vx_u96_add) in place. The backend runs the x, y and z scans in turn.

layout(local_size_x = 64) in;

uniform int vx_scan_axis;     // 0 = x, 1 = y, 2 = z
uniform int vx_line_offset;   // first line of this dispatch

layout(std430, binding = VX_BIND_SAT_SCAN) buffer SatScan { uint vx_scan[]; };   // the word layout of vx_sat.h

VxU96 vx_scan_load(int plane, int e) {
    VxU96 v;
    v.lo = vx_scan[vx_sat_word_index(plane, 0, e)];
    v.mid = vx_scan[vx_sat_word_index(plane, 1, e)];
    v.hi = vx_scan[vx_sat_word_index(plane, 2, e)];
    return v;
}

void main() {
    int sx = S.dims.x + 1;
    int sy = S.dims.y + 1;
    int sz = S.dims.z + 1;
    int n = vx_scan_axis == 0 ? sx : (vx_scan_axis == 1 ? sy : sz);
    int lines = sx * sy * sz / n;
    int line = int(gl_GlobalInvocationID.x) + vx_line_offset;
    if (line >= lines * S.planes) return;
    int l = line % lines;
    int plane = line / lines;
    int base = 0;
    int stride = 1;
    if (vx_scan_axis == 0) {
        base += l * sx;
    } else if (vx_scan_axis == 1) {
        base += (l / sx) * sx * sy + l % sx;
        stride = sx;
    } else {
        base += l;
        stride = sx * sy;
    }
    VxU96 run = vx_scan_load(plane, base);
    for (int k = 1; k < n; ++k) {
        int e = base + k * stride;
        run = vx_u96_add(run, vx_scan_load(plane, e));
        vx_scan[vx_sat_word_index(plane, 0, e)] = run.lo;
        vx_scan[vx_sat_word_index(plane, 1, e)] = run.mid;
        vx_scan[vx_sat_word_index(plane, 2, e)] = run.hi;
    }
}
