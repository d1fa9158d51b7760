// Shared-kernel prelude: lets the vx_*.h headers compile both as GLSL 4.50 and as C++17 with GLM.
// On the GL side the headers are concatenated after "#define VX_GLSL" (see src/kernel/shader_source.cpp),
// with their #include / #pragma once lines stripped. On the C++ side they are #included inside a
// struct body (src/kernel/cpu_kernel.h), so backend data accessors are members and the math is one copy.
//
// Rules for code in vx_*.h:
//  - out/inout parameters use VX_OUT(T) / VX_INOUT(T); no pointers, no references otherwise;
//  - no `const` locals (GLSL wants constant expressions there), no swizzles beyond .x/.y/.z/.w;
//  - structs are filled field by field (no constructors), constants are #defines;
//  - data comes only from accessor functions that each backend defines:
//      float  vx_atlas_density(int index);   vec3 vx_atlas_color(int index);
//      float  vx_atlas_surface(int index);
//      float  vx_atlas_emission(int index);  ivec4 vx_page_entry(int index);
//      vec3   vx_atlas_velocity(int index);  (render.motion_blur's velocity grid)
//      VxLight vx_light(int index);          vec4  vx_tf_lut(int index);
//      vec4   vx_emission_lut(int index);    (emission tables, VX_EMISSION_LUT_SIZE rows per source)
//      float  vx_cache(int index);           (light cache, read by the march)
//      uint   vx_sat_word(int index);        (SAT, 3 words per entry, read by the light passes)
//      float  vx_illum(int index);           (illumination volume, read by the march)
//      vec4   vx_noise(int index);           (perturbation table)
//      float  vx_prop_sigma(int index), vx_prop_prev(int index), vx_prop_in(int index)
//                                            (a propagation sweep's grid, previous slice, input)
//    and read the parameters in VxParams through the global/member `P`.
#ifdef VX_GLSL
#define VX_OUT(T) out T
#define VX_INOUT(T) inout T
#define VX_INLINE
#define VX_SIMD_LOOP
#define VX_SIMD_SUM(var)
#else
#define VX_OUT(T) T&
#define VX_INOUT(T) T&
// The CPU march is only fast when the per-sample functions inline into the SIMD loops.
#define VX_INLINE [[gnu::always_inline]] inline
// Iterations are independent: vectorise across them (needs -fopenmp-simd).
#define VX_SIMD_LOOP _Pragma("omp simd")
#define VX_PRAGMA(text) _Pragma(#text)
#define VX_SIMD_SUM(var) VX_PRAGMA(omp simd reduction(+ : var))
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
#define VX_EMISSION_LUT_SIZE 256   // rows of one source's table: radiance over grid values [0, max]
#define VX_CHUNK 16                // samples whose extinction is evaluated together (one SIMD batch)
#define VX_NOISE_SIZE 32           // perturbation noise table edge (power of two); the table repeats
#define VX_LANES 8                 // batches run in whole multiples of this (the CPU's SIMD width)

#define VX_LIGHT_DIRECTIONAL 0
#define VX_LIGHT_POINT 1
#define VX_LIGHT_SPOT 2

#define VX_SHADOWS_NONE 0
#define VX_SHADOWS_RAYMARCH 1
#define VX_SHADOWS_SAT_CONE 2      // shadow optical depth read from the light cache
#define VX_SHADOWS_PROPAGATION 3   // direct and indirect light read from the illumination volume

#define VX_FILTER_TRILINEAR 0      // P.voxel_filter: how the atlas is reconstructed between voxels
#define VX_FILTER_TRICUBIC 1

// GL binding points of every program, each once (uniform blocks and storage buffers count apart).
// The GL backend binds buffers by block name; these numbers keep the blocks of one program apart,
// and grade.comp's pixels are bound by number (src/grade/gl_color_transform.cpp).
#define VX_BIND_PARAMS 0           // uniform VxParams P
#define VX_BIND_SAT_PARAMS 1       // uniform VxSatParams S (light passes)
#define VX_BIND_PROP_PARAMS 2      // uniform VxPropParams Q (propagation sweeps)
#define VX_BIND_ATLAS_DENSITY 0
#define VX_BIND_ATLAS_EMISSION 1
#define VX_BIND_ATLAS_VECTORS 2    // colour, then velocity
#define VX_BIND_PAGE_TABLE 3
#define VX_BIND_LIGHTS 4
#define VX_BIND_TRANSFER_LUT 5
#define VX_BIND_BAND 6             // march.comp: the rows it writes
#define VX_BIND_LIGHT_CACHE 7
#define VX_BIND_SAT 8
#define VX_BIND_NEEDED 9           // light_cache.comp: cells to compute
#define VX_BIND_CHANNEL 10         // light_cache.comp: the channel it writes
#define VX_BIND_ILLUMINATION 11
#define VX_BIND_NOISE 12
#define VX_BIND_PROP_SIGMA 13
#define VX_BIND_SLICE_IN 14
#define VX_BIND_VOLUME 15          // propagate.comp: the RGB block it writes
#define VX_BIND_SLICE_OUT 16
#define VX_BIND_SWEEP_INPUT 17
#define VX_BIND_EMISSION_LUT 18
#define VX_BIND_SAT_SCAN 19        // sat_scan.comp: the table it scans
#define VX_BIND_PIXELS 20          // grade.comp: the pixels it transforms
#define VX_BIND_DEEP_BAND 21       // march.comp: the rows' deep samples (output.deep)

#define VX_LIGHTS_ALL 0            // which lights vx_in_scattered sums
#define VX_LIGHTS_DIRECTIONAL 1
#define VX_LIGHTS_LOCAL 2
