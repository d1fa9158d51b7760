// GL entry point of the grade stage: one invocation per pixel of a block of premultiplied RGBA,
// transformed in place by an OCIO processor's generated function, ocio_transform (assembled just
// before this file, with its LUT samplers and uniforms; see src/grade/gl_color_transform.cpp), between
// the premultiplication rules of vx_grade.h.

layout(local_size_x = 64) in;

uniform int vx_pixel_count;     // pixels in this block
uniform bool vx_unpremultiply;

layout(std430, binding = VX_BIND_PIXELS) buffer Pixels { vec4 vx_pixels[]; };

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= vx_pixel_count) return;
    vec4 c = vx_pixels[i];
    vx_pixels[i] = vx_grade_output(ocio_transform(vx_grade_input(c, vx_unpremultiply)), c, vx_unpremultiply);
}
