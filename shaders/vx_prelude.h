// Shared-kernel prelude: lets the vx_*.h headers compile both as GLSL 4.50 and as C++17 with GLM.
// On the GL side the headers are concatenated after "#define VX_GLSL" (see src/kernel/shader_source.cpp),
// with their #include / #pragma once lines stripped. On the C++ side they are #included inside a
// struct body (src/kernel/cpu_kernel_data.h, cpu_kernel.h), so backend data accessors are members and the math is one copy.
//
// Rules for code in vx_*.h:
//  - out/inout parameters use VX_OUT(T) / VX_INOUT(T), a large input struct may use VX_IN(T); no
//    pointers, no references otherwise;
//  - no `const` locals (GLSL wants constant expressions there), no swizzles beyond .x/.y/.z/.w;
//  - structs are filled field by field (no constructors), constants are #defines;
//  - data comes only from accessor functions each backend defines, generated from the one list of
//    the kernel's arrays (CMakeLists.txt's voxlux_kernel_data, each method's method.cmake):
//    vx_atlas_density(i), vx_light(i), vx_cache(i), ... (vx_gl_data.glsl on GL, vx_cpu_data.inc on
//    the CPU), and the parameters through the globals/members `P` (VxParams), `L` (VxLighting: each
//    lighting method's block) and a pass's own block.
#ifdef VX_GLSL
#define VX_IN(T) in T
#define VX_OUT(T) out T
#define VX_INOUT(T) inout T
#define VX_INLINE
#define VX_SIMD_LOOP
#define VX_SIMD_SUM(var)
#define VX_UNUSED(x)
#else
// An input struct passed to a function the compiler does not inline, without its copy.
#define VX_IN(T) const T&
#define VX_OUT(T) T&
#define VX_INOUT(T) T&
// The CPU march is only fast when the per-sample functions inline into the SIMD loops.
#define VX_INLINE [[gnu::always_inline]] inline
// Iterations are independent: vectorise across them (needs -fopenmp-simd).
#define VX_SIMD_LOOP _Pragma("omp simd")
#define VX_PRAGMA(text) _Pragma(#text)
#define VX_SIMD_SUM(var) VX_PRAGMA(omp simd reduction(+ : var))
#define VX_UNUSED(x) (void)(x)
#endif

// VX_CHECK_INDEX(i, n, what) traps an index i outside [0, n) in a C++ build with VX_BOUNDS_CHECK
// (the backend's array accessors check the same way); elsewhere it is nothing.
#if defined(VX_GLSL) || !defined(VX_BOUNDS_CHECK)
#define VX_CHECK_INDEX(i, n, what)
#else
#define VX_CHECK_INDEX(i, n, what) \
    if ((i) < 0 || (i) >= (n)) vx_bounds_trap(what, i, n)
#endif

#define VX_PI 3.14159265f
#define VX_BRICK 8                 // voxels per brick edge (one OpenVDB leaf)
#define VX_BRICK_STRIDE 9          // stored edge: brick + 1-voxel apron on the + side for trilinear
#define VX_BRICK_VOXELS 729        // VX_BRICK_STRIDE^3
#define VX_PAGE_EMPTY -1
#define VX_REGION_SHIFT 3          // a region (the march's coarse empty-space level) is 8^3 bricks
#define VX_REGION_BRICKS (1 << VX_REGION_SHIFT)
#define VX_TF_LUT_SIZE 256
#define VX_MAX_EMISSION 4          // emission sources (grids) per scene
#define VX_MAX_VOLUMES 256         // volumes and instances a scene places (a GL uniform block of them)
#define VX_MAX_LINK_SETS 32        // light linking's link sets (bits of VxVolume.lit_sets)
#define VX_ALL_LINKS (-1)          // every volume lights and shadows (no link set)
#define VX_ROLE_VISIBLE 0          // VxVolume::role: seen by the camera
#define VX_ROLE_MATTE 1            // occludes camera and light rays, no colour or alpha of its own
#define VX_ROLE_SHADOW_ONLY 2      // occludes light rays only
#define VX_EMISSION_LUT_SIZE 256   // rows of one source's table: radiance over grid values [0, max]
#define VX_CHUNK 16                // samples whose extinction is evaluated together (one SIMD batch)
#define VX_NOISE_SIZE 32           // perturbation noise table edge (power of two); the table repeats
#define VX_LANES 8                 // batches run in whole multiples of this (the CPU's SIMD width)

#define VX_LIGHT_DIRECTIONAL 0
#define VX_LIGHT_POINT 1
#define VX_LIGHT_SPOT 2

#define VX_FILTER_TRILINEAR 0      // P.voxel_filter: how the atlas is reconstructed between voxels
#define VX_FILTER_TRICUBIC 1

// GL binding points of every program, each once: generated from the kernel's declared blocks.
// The GL backend binds buffers by block name; these numbers keep the blocks of one program apart,
// and grade.comp's pixels are bound by number (src/grade/gl_color_transform.cpp).
#include "vx_kernel_bindings.h"

#define VX_LIGHTS_ALL 0            // which lights vx_in_scattered sums
#define VX_LIGHTS_DIRECTIONAL 1
#define VX_LIGHTS_LOCAL 2
