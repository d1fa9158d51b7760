// GL entry point of the march: one invocation per pixel of a band of rows, running the shared
// kernel (vx_march.h) and writing the pixel's AOVs. The backend dispatches the image band by band.

layout(local_size_x = 8, local_size_y = 8) in;

uniform int vx_row_offset;   // image row of the band's first row
uniform int vx_ray;          // which of a pixel's P.time_samples rays (vx_render_ray)

// 20 floats per pixel of the band, row-major: rgba, direct, ambient, emission, indirect,
// transmittance, depth, samples, pad (the byte layout of the C++ VxPixel).
layout(std430, binding = VX_BIND_BAND) writeonly buffer Band { float vx_band[]; };
// With P.deep_samples > 0: per pixel of the band, its sample count then 6 floats a sample (rgb,
// alpha, z, z_back: VxDeepSample's member order), 1 + 6 * P.deep_samples floats in all.
layout(std430, binding = VX_BIND_DEEP_BAND) writeonly buffer DeepBand { float vx_deep_band[]; };

void main() {
    int x = int(gl_GlobalInvocationID.x);
    int y = int(gl_GlobalInvocationID.y);
    if (x >= P.width || y + vx_row_offset >= P.height) return;
    VxDeepRay deep;
    VxPixel px = vx_render_ray(x, y + vx_row_offset, vx_ray, deep);
    if (P.deep_samples > 0) {
        int d = (1 + 6 * P.deep_samples) * (y * P.width + x);
        vx_deep_band[d] = float(deep.count);
        for (int i = 0; i < deep.count; ++i) {
            int e = d + 1 + 6 * i;
            vx_deep_band[e] = deep.s[i].rgb.x;
            vx_deep_band[e + 1] = deep.s[i].rgb.y;
            vx_deep_band[e + 2] = deep.s[i].rgb.z;
            vx_deep_band[e + 3] = deep.s[i].alpha;
            vx_deep_band[e + 4] = deep.s[i].z;
            vx_deep_band[e + 5] = deep.s[i].z_back;
        }
    }
    int o = 20 * (y * P.width + x);
    vx_band[o] = px.rgba.x;
    vx_band[o + 1] = px.rgba.y;
    vx_band[o + 2] = px.rgba.z;
    vx_band[o + 3] = px.rgba.w;
    vx_band[o + 4] = px.direct.x;
    vx_band[o + 5] = px.direct.y;
    vx_band[o + 6] = px.direct.z;
    vx_band[o + 7] = px.ambient.x;
    vx_band[o + 8] = px.ambient.y;
    vx_band[o + 9] = px.ambient.z;
    vx_band[o + 10] = px.emission.x;
    vx_band[o + 11] = px.emission.y;
    vx_band[o + 12] = px.emission.z;
    vx_band[o + 13] = px.indirect.x;
    vx_band[o + 14] = px.indirect.y;
    vx_band[o + 15] = px.indirect.z;
    vx_band[o + 16] = px.transmittance;
    vx_band[o + 17] = px.depth;
    vx_band[o + 18] = px.samples;
    vx_band[o + 19] = 0.0f;
}
