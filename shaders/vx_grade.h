// Grade stage: how a colour transform meets premultiplied RGBA. Colour transforms (CDL offsets,
// looks, display views) are defined on unpremultiplied colour, so a pixel with alpha > 0 is
// divided by alpha, transformed, and multiplied back. A pixel with alpha 0 and no colour (the
// background) stays black; one with alpha 0 but colour (emission from a medium too thin to
// absorb) is transformed as it is. Alpha never changes. Both backends wrap the OCIO transform
// (CPU processor, or its generated GLSL) in these two functions.
#pragma once
#include "vx_prelude.h"

VX_INLINE vec4 vx_grade_input(vec4 c, bool unpremultiply) {
    if (unpremultiply && c.w > 0.0f) return vec4(c.x / c.w, c.y / c.w, c.z / c.w, c.w);
    return c;
}

VX_INLINE vec4 vx_grade_output(vec4 graded, vec4 original, bool unpremultiply) {
    if (!unpremultiply) return vec4(graded.x, graded.y, graded.z, original.w);
    if (original.w > 0.0f) return vec4(graded.x * original.w, graded.y * original.w, graded.z * original.w, original.w);
    if (original.x == 0.0f && original.y == 0.0f && original.z == 0.0f) return vec4(0.0f);
    return vec4(graded.x, graded.y, graded.z, original.w);
}
