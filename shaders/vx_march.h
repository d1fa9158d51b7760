// Ray marching through the brick atlas: the brick walk of vx_dda.h, which skips empty space, optical depth
// accumulated as a sum (tau += sigma * dt, T = exp(-tau)), brute-force shadow rays, compositing.
// The light a sample scatters comes from the lighting methods through the vx_lighting_* hooks
// (generated from the registered methods, cmake/kernel_contract.cmake), so no method is named here.
#pragma once
#include "vx_dda.h"
#include "vx_deep.h"
#include "vx_motion.h"
#include "vx_lighting.h"
#include "vx_noise.h"
#include "vx_pixel.h"
#include "vx_surface.h"
#include "vx_volumes.h"

// Extinction at index point p (world point x) under the perturbation (Kniss 2003 Sec. III.D):
// the lookup displaced by the noise vector, the result scaled by the noise.
float vx_perturbed_extinction(vec3 p, vec3 x) {
    vec4 n = vx_noise_fbm(x);
    float v = vx_density_index(vx_displaced() ? p + vec3(n) * P.displacement : p);   // one lookup inlined, not two
    return vx_perturb_extinction(vx_value_extinction(v), n);
}

// Extinction at the first `lanes` (a multiple of VX_LANES, at most VX_CHUNK) of the consecutive
// samples t_j = (k + j + 0.5) * dt inside one brick. The samples are independent, so the C++
// build evaluates trilinear ones as one SIMD batch (gathers from the atlas); a GPU thread runs the
// loop. Tricubic samples are looked up one by one (their taps may cross into other bricks).
// The batch's samples past the first n (past the brick) read clamped, in-bounds voxels; the
// one-by-one lookups set them to 0; the caller ignores them. Under a
// perturbation every sample is looked up on its own (its displaced point may lie in any brick);
// wo + wd * t is the sample's world point. A ray at a `time` where the medium moves looks each
// sample up where the medium was (vx_motion.h) and keeps how far it moved in `shift`.
struct VxChunk {
    float sigma[VX_CHUNK];
    float tau[VX_CHUNK];    // optical depth from the camera to the end of each sample's segment
    float T[VX_CHUNK];      // exp(-tau)
    vec3 shift[VX_CHUNK];   // world distance the medium at each sample has moved (set while moving)
};

// The moved samples' extinction in place of the unmoved ones that vx_chunk_extinction looked up,
// for the first n lanes: the brick's own samples (the caller ignores the rest).
VX_INLINE void vx_chunk_move(int slot, ivec3 brick, vec3 o, vec3 d, int k, int n, float dt, float time, VX_INOUT(VxChunk) c) {
    for (int j = 0; j < n; ++j) {
        float t = (float(k + j) + 0.5f) * dt;
        vec3 p = o + d * t;
        c.shift[j] = vx_motion_shift(slot, brick, p, time);
        if (vx_is_zero(c.shift[j])) continue;
        bool found;
        VxTaps moved = vx_moved_taps(slot, brick, p, c.shift[j], found);
        c.sigma[j] = found ? vx_extinction(moved) : 0.0f;
    }
}

// Trilinear density at t along a ray inside stored brick `slot`, `local` being the ray's origin
// minus the brick's first voxel: scalars only, so that the CPU's SIMD loops over t vectorise.
VX_INLINE float vx_brick_density(int slot, vec3 local, vec3 d, float t) {
    return VX_TRILINEAR(vx_atlas_density, vx_corners(slot, local.x + d.x * t, local.y + d.y * t, local.z + d.z * t));
}

VX_INLINE void vx_chunk_extinction(int slot, ivec3 brick, vec3 o, vec3 d, vec3 wo, vec3 wd, int k, int n, int lanes, float dt,
                                   float time, VX_INOUT(VxChunk) c) {
    if (vx_perturbed()) {
        bool moving = vx_moving(time);
        for (int j = 0; j < n; ++j) {
            float t = (float(k + j) + 0.5f) * dt;
            vec3 p = o + d * t;
            vec3 shift = vx_motion_shift(slot, brick, p, time);
            if (moving) c.shift[j] = shift;
            c.sigma[j] = vx_perturbed_extinction(p - vx_to_index_dir(shift), wo + wd * t - shift);
        }
        for (int j = n; j < lanes; ++j) c.sigma[j] = 0.0f;
        return;
    }
    if (VX_VOXEL_FILTER != VX_FILTER_TRILINEAR) {
        for (int j = 0; j < n; ++j) {
            float t = (float(k + j) + 0.5f) * dt;
            c.sigma[j] = vx_extinction(vx_taps_at(slot, brick, o + d * t));
        }
        for (int j = n; j < lanes; ++j) c.sigma[j] = 0.0f;
        if (vx_moving(time)) vx_chunk_move(slot, brick, o, d, k, n, dt, time, c);
        return;
    }
    // Scalars only inside the loops (vector temporaries would be spilled per SIMD lane); two loops
    // because reconstruction vectorises on its own and the transfer-function branch is uniform,
    // so the compiler hoists it out of the second.
    vec3 local = o - vec3(brick * VX_BRICK);
    VX_SIMD_LOOP
    for (int j = 0; j < lanes; ++j)
        c.sigma[j] = vx_brick_density(slot, local, d, (float(k + j) + 0.5f) * dt);
    VX_SIMD_LOOP
    for (int j = 0; j < lanes; ++j)
        c.sigma[j] = vx_value_extinction(c.sigma[j]);
    if (vx_moving(time)) vx_chunk_move(slot, brick, o, d, k, n, dt, time, c);
}

// Optical depth of a ray's samples t_k = (k + 0.5) * dt, k in [k0, k1), inside brick (slot, b),
// in the medium at the frame's own time; x + wi * t is a sample's world point. Trilinear samples
// are one SIMD sum on the CPU (gathers from the atlas, as vx_chunk_extinction's); perturbed and
// tricubic ones are looked up one by one.
VX_INLINE float vx_brick_optical_depth(int slot, ivec3 b, vec3 o, vec3 d, vec3 x, vec3 wi, int k0, int k1, float dt) {
    float sum = 0.0f;
    if (vx_perturbed()) {
        for (int k = k0; k < k1; ++k) {
            float t = (float(k) + 0.5f) * dt;
            sum += vx_perturbed_extinction(o + d * t, x + wi * t);
        }
        return sum * dt;
    }
    if (VX_VOXEL_FILTER != VX_FILTER_TRILINEAR) {
        for (int k = k0; k < k1; ++k) {
            float t = (float(k) + 0.5f) * dt;
            sum += vx_extinction(vx_taps_at(slot, b, o + d * t));
        }
        return sum * dt;
    }
    vec3 local = o - vec3(b * VX_BRICK);
    VX_SIMD_SUM(sum)
    for (int k = k0; k < k1; ++k) sum += vx_value_extinction(vx_brick_density(slot, local, d, (float(k) + 0.5f) * dt));
    return sum * dt;
}

// Whether the march is through several volumes (vx_volumes.h). GL compiles that march only into the
// programs of scenes of several (VX_MARCH_VOLUMES, src/backend/gl), as it compiles one filter a
// program: llvmpipe's compile time follows the code a program holds.
#if defined(VX_GLSL) && !defined(VX_MARCH_VOLUMES)
#define VX_SEVERAL_VOLUMES false
#else
#define VX_SEVERAL_VOLUMES (P.volume_count > 0)
#endif

// Transmittance from world point x towards a light at distance `dist` along unit direction wi,
// through the volumes that shadow link set `link`'s lights (VX_ALL_LINKS: every volume).
// Reference quality: fixed step P.shadow_step, stops only below the transmittance cutoff.
float vx_shadow_transmittance(vec3 x, vec3 wi, float dist, int link) {
    if (VX_SEVERAL_VOLUMES) {
        float tau_cut = -log(P.transmittance_cutoff);
        float tau = vx_volumes_optical_depth(x, wi, dist, P.shadow_step, tau_cut, link);
        return tau > tau_cut ? 0.0f : vx_exp(-tau);
    }
    vec3 o = vx_to_index_point(x);
    vec3 d = vx_to_index_dir(wi);
    float t0 = 0.0f;
    float t1 = dist;
    if (!vx_clip_to_bricks(o, d, t0, t1)) return 1.0f;
    float dt = P.shadow_step;
    float inv_dt = 1.0f / dt;
    float tau = 0.0f;
    float tau_cut = -log(P.transmittance_cutoff);
    VxDda s = vx_dda_begin(o, d, t0, t1);
    bool skips = vx_skips_regions();
    ivec3 region = vx_no_region();
    vx_dda_skip_empty(s, region, skips);
    while (s.t < s.t_end) {
        int slot = vx_page_lookup(s.brick);
        if (vx_visits(slot)) {
            tau += vx_brick_optical_depth(slot, s.brick, o, d, x, wi, vx_first_sample(s.t, inv_dt), vx_first_sample(vx_dda_exit(s), inv_dt), dt);
            if (tau > tau_cut) return 0.0f;
        }
        vx_dda_next(s, region, skips);
    }
    return vx_exp(-tau);
}

// The lighting methods' block of light (an illumination volume's) that the march's light group
// and link set `link` read: one per group and link set, group by group.
VX_INLINE int vx_light_block(int link) { return P.light_group * max(P.link_sets, 1) + max(link, 0); }

// Single-scattered light at world point x for a camera ray travelling along unit direction dir,
// from the lights `which` selects (VX_LIGHTS_*) of the march's light group and of link set `link`
// (VX_ALL_LINKS: every light). Unshadowed directional light is the same all
// along a ray, so the march sums it once per ray and asks here for the local lights only.
// `lit` is what the lighting methods looked up at x; `surface` is vx_surface; g the medium's
// Henyey-Greenstein anisotropy there.
vec3 vx_in_scattered(vec3 x, vec3 dir, int which, VX_IN(VxLightingSample) lit, VxSurface surface, float g, int link) {
    vec3 sum = vec3(0.0f);
    vec3 unshadowed = vec3(0.0f);   // what the lights would bring unshadowed
    for (int i = 0; i < P.light_count; ++i) {
        VxLight light = vx_light(i);
        bool directional = light.type == VX_LIGHT_DIRECTIONAL;
        if ((which == VX_LIGHTS_DIRECTIONAL && !directional) || (which == VX_LIGHTS_LOCAL && directional)) continue;
        if (light.group != P.light_group || (link != VX_ALL_LINKS && light.link_set != link)) continue;
        vec3 wi;
        float dist;
        vec3 e = vx_light_incident(light, x, wi, dist);
        if (e.x + e.y + e.z <= 0.0f) continue;
        float shadow = P.shadow_rays != 0 ? vx_shadow_transmittance(x, wi, dist, link) : 1.0f;
        shadow *= vx_lighting_shadow(lit, i);
        unshadowed = vx_radiance_add(unshadowed, e);
        sum = vx_radiance_add(sum, e * (shadow * vx_phase_hg(dot(wi, dir), g) * vx_surface_factor(surface, wi, dir)));
    }
    return vx_lighting_direct(lit, sum, unshadowed, vx_light_block(link));
}

// Optical depth is accumulated as a sum (Schlegel 2011, Eq. 2) and turned into transmittance
// per sample, not multiplied up sample by sample; the exponentials are one SIMD batch.
VX_INLINE void vx_chunk_transmittance(float tau, int lanes, float dt, VX_INOUT(VxChunk) c) {
    for (int j = 0; j < lanes; ++j) {
        tau += c.sigma[j] * dt;
        c.tau[j] = tau;
    }
    VX_SIMD_LOOP
    for (int j = 0; j < lanes; ++j)
        c.T[j] = vx_exp(-c.tau[j]);
}

// Sum over the chunk's first n samples of (light absorbed in the sample's segment) * t, for the
// opacity-weighted depth; T_before is the transmittance before the chunk.
VX_INLINE float vx_chunk_depth(float T_before, int k, int n, int lanes, float dt, VX_INOUT(VxChunk) c) {
    float sum = 0.0f;
    VX_SIMD_SUM(sum)
    for (int j = 0; j < lanes; ++j) {
        float before = j == 0 ? T_before : c.T[max(j - 1, 0)];
        sum += j < n ? (before - c.T[j]) * ((float(k + j) + 0.5f) * dt) : 0.0f;
    }
    return sum;
}

// A marched ray's pixel from its AOV sums, its transmittance T, its alpha (1 - T, or with mattes
// the visible volumes' coverage) and its opacity-weighted depth sum.
VxPixel vx_finish_ray(VxPixel px, float T, float alpha, float depth_weighted, VX_INOUT(VxDeepRay) deep) {
    px.rgba = vec4(vx_pixel_radiance(px), alpha);
    if (P.deep_samples > 0) vx_deep_close(deep, T, vec3(px.rgba));
    px.transmittance = T;
    px.depth = alpha > 0.0f ? depth_weighted / alpha : 0.0f;
    return px;
}

// March one camera ray through several volumes (vx_volumes.h): at the samples t_k = (k + 0.5) * dt
// the one volume's march takes, each the volumes' summed medium, shaded with its mixed albedo and
// g; the space between the volumes' boxes is jumped. Sample by sample, without the one volume's
// SIMD batches. The ray is attenuated by the visible volumes and the mattes; the light the
// visible ones absorb is the pixel's alpha (1 - T without mattes), so a matte cuts what is behind
// it and adds nothing. The visible volumes' emission is integrated as the one volume's is. With
// light linking, each link set's lights are scattered by the visible volumes they light (their
// scattering over the camera's extinction, and their g), a lookup of the volumes per link set; the
// indirect light is scattered by every visible volume. At a
// `time` within the shutter each volume is where its velocity moved it; the light a sample
// receives is the frame's own at the sample's point (the volumes move each on its own, so no one
// motion carries the light along, as the one volume's march does).
VxPixel vx_march_volumes(vec3 origin, vec3 dir, vec3 forward, float time, float t_cut, VX_INOUT(VxDeepRay) deep) {
    VxPixel px = vx_empty_pixel();
    vx_deep_begin(deep);
    float t0 = 0.0f;
    float t1 = 1e30f;
    if (!vx_volumes_clip(origin, dir, t0, t1)) return px;
    float dt = P.step;
    t1 = min(t1, t_cut + 0.5f * dt);   // the samples whose segments start before the holdout
    bool deep_on = P.deep_samples > 0;
    bool lit_indirect = vx_lighting_indirect_on();
    float tau = 0.0f;
    float T = 1.0f;
    float coverage = 0.0f;
    float depth_weighted = 0.0f;
    float cos_forward = dot(dir, forward);
    VxMedium m;
    for (int k = vx_first_sample(t0, 1.0f / dt); T > P.transmittance_cutoff && vx_volumes_sample(origin, dir, dt, t1, true, time, VX_ALL_LINKS, k, m); ++k) {
        float t = (float(k) + 0.5f) * dt;
        vec3 x = origin + dir * t;
        px.samples += 1.0f;
        float share = vx_cut_share(k, dt, t_cut);   // 1 but at a holdout
        m.sigma_camera *= share;
        m.sigma_visible *= share;
        m.scattering *= share;
        vec3 le = m.emitted * share;
        if (m.sigma_camera <= 0.0f && le.x + le.y + le.z <= 0.0f) continue;
        if (deep_on) vx_deep_span(deep, float(k) * dt * cos_forward, min(float(k + 1) * dt, t_cut) * cos_forward, T, vx_pixel_radiance(px), tau);
        tau += m.sigma_camera * dt;
        float T_next = vx_exp(-tau);
        float absorbed = T - T_next;
        px.emission = vx_radiance_add(px.emission, le * (T * dt * vx_exp_integral(m.sigma_camera * dt)));   // as the one volume's march
        T = T_next;
        if (m.sigma_visible <= 0.0f) continue;   // a matte's stretch: it cuts, and adds nothing
        vec3 albedo = vx_medium_albedo(m, m.sigma_camera);
        float seen = absorbed * (m.sigma_visible / m.sigma_camera);
        coverage += seen;
        VxLightingSample lit = vx_lighting_sample(x);
        for (int link = P.link_sets > 0 ? 0 : VX_ALL_LINKS; link < P.link_sets; ++link) {
            vec3 linked_albedo = albedo;
            float g = vx_medium_g(m);
            if (link != VX_ALL_LINKS) {
                bool in_box;
                VxMedium linked = vx_volumes_medium(x, true, time, link, in_box);
                linked_albedo = vx_medium_albedo(linked, linked.sigma_camera);   // the camera's extinction is every volume's
                g = vx_medium_g(linked);
            }
            vec3 incident = vx_in_scattered(x, dir, VX_LIGHTS_ALL, lit, vx_no_surface(), g, link);
            px.direct = vx_radiance_add(px.direct, linked_albedo * incident * absorbed);
            if (lit_indirect) px.indirect = vx_radiance_add(px.indirect, albedo * vx_lighting_indirect(lit, vx_light_block(link)) * absorbed);
        }
        px.ambient = vx_radiance_add(px.ambient, albedo * P.ambient * vx_lighting_ambient(lit) * absorbed);
        depth_weighted += seen * t * cos_forward;
    }
    return vx_finish_ray(px, T, P.volume_roles != 0 ? coverage : 1.0f - T, depth_weighted, deep);
}

// March one camera ray (world origin, unit world direction, camera forward for depth) at `time`
// (frames from the frame's own, vx_motion.h), up to a holdout at distance t_cut (1e30: none). With P.deep_samples > 0 the ray's deep samples go
// to `deep` (vx_deep.h). Under motion blur every lookup of a sample (medium, lights, the light
// stages' volumes) is made where the medium was at `time`: the light stages are the frame's own,
// carried along with the medium.
VxPixel vx_march_ray(vec3 origin, vec3 dir, vec3 forward, float time, float t_cut, VX_INOUT(VxDeepRay) deep) {
    if (VX_SEVERAL_VOLUMES) return vx_march_volumes(origin, dir, forward, time, t_cut, deep);
    VxPixel px = vx_empty_pixel();
    vx_deep_begin(deep);
    bool deep_on = P.deep_samples > 0;

    vec3 o = vx_to_index_point(origin);
    vec3 d = vx_to_index_dir(dir);
    float t0 = 0.0f;
    float t1 = 1e30f;
    if (!vx_clip_to_bricks(o, d, t0, t1)) return px;

    float dt = P.step;
    t1 = min(t1, t_cut + 0.5f * dt);   // the samples whose segments start before the holdout
    if (t0 >= t1) return px;
    float cutoff = P.transmittance_cutoff;
    bool shaded_surface = P.surface_inv_range > 0.0f;
    bool per_ray_directional = P.shadow_rays == 0 && !vx_lighting_shadows() && !shaded_surface;
    vec3 directional = per_ray_directional ? vx_in_scattered(origin, dir, VX_LIGHTS_DIRECTIONAL, vx_lighting_sample(origin), vx_no_surface(), P.anisotropy, VX_ALL_LINKS)
                                           : vec3(0.0f);
    bool lit_varies = vx_lighting_varies();
    bool lit_indirect = vx_lighting_indirect_on();
    vec3 ambient = P.ambient;
    int per_sample_lights = per_ray_directional ? VX_LIGHTS_LOCAL : VX_LIGHTS_ALL;
    bool emits = P.emission_sources > 0;
    bool plain_albedo = P.use_transfer == 0 && P.use_color_grid == 0;
    bool surface_grid = shaded_surface && P.use_surface_grid != 0;
    // When the light a sample scatters is the same all along the ray (unshadowed directional
    // lights and unoccluded ambient only, one albedo, no emission), a chunk's scattered light
    // telescopes exactly to albedo * L * (T before - T after): no per-sample work beyond the
    // SIMD batches.
    bool constant_light = per_ray_directional && plain_albedo && !emits && P.local_light_count == 0 && !lit_varies;
    bool moving = vx_moving(time);
    float tau = 0.0f;
    float T = 1.0f;
    float depth_weighted = 0.0f;
    float cos_forward = dot(dir, forward);
    VxChunk chunk;
    VxDda s = vx_dda_begin(o, d, t0, t1);
    float inv_dt = 1.0f / dt;
    bool skips = vx_skips_regions();
    ivec3 region = vx_no_region();
    vx_dda_skip_empty(s, region, skips);
    while (s.t < s.t_end && T > cutoff) {
        int slot = vx_page_lookup(s.brick);
        bool occupied = slot != VX_PAGE_EMPTY;
        int k_end = vx_visits(slot) ? vx_first_sample(vx_dda_exit(s), inv_dt) : 0;
        for (int k = vx_first_sample(s.t, inv_dt); k < k_end && T > cutoff; k += VX_CHUNK) {
            int n = min(VX_CHUNK, k_end - k);
            // A brick often holds only a few samples of a ray: evaluate whole SIMD widths, not the
            // whole batch.
            int lanes = min(VX_CHUNK, (n + VX_LANES - 1) / VX_LANES * VX_LANES);
            vx_chunk_extinction(slot, s.brick, o, d, origin, dir, k, n, lanes, dt, time, chunk);
            bool cut = float(k + n) * dt > t_cut;   // the chunk reaches the holdout
            if (cut)
                for (int j = 0; j < n; ++j) chunk.sigma[j] *= vx_cut_share(k + j, dt, t_cut);
            vx_chunk_transmittance(tau, lanes, dt, chunk);
            px.samples += float(n);
            if (constant_light) {
                if (deep_on) {   // the chunk as one stretch, from its first to its last sample with medium
                    int first = n;
                    int last = -1;
                    for (int j = 0; j < n; ++j) {
                        if (chunk.sigma[j] > 0.0f) {
                            first = min(first, j);
                            last = j;
                        }
                    }
                    if (last >= 0)
                        vx_deep_span(deep, float(k + first) * dt * cos_forward, min(float(k + last + 1) * dt, t_cut) * cos_forward, T,
                                     vx_pixel_radiance(px), tau);
                }
                float T_after = chunk.T[n - 1];
                px.direct = vx_radiance_add(px.direct, P.albedo * directional * (T - T_after));
                px.ambient = vx_radiance_add(px.ambient, P.albedo * ambient * (T - T_after));
                depth_weighted += vx_chunk_depth(T, k, n, lanes, dt, chunk) * cos_forward;
                tau = chunk.tau[n - 1];
                T = T_after;
                continue;
            }
            for (int j = 0; j < n; ++j) {
                float sigma = chunk.sigma[j];
                float t = (float(k + j) + 0.5f) * dt;
                vec3 p = o + d * t;
                vec3 shift = moving ? chunk.shift[j] : vec3(0.0f);
                bool here = occupied;    // whether the sample's medium lies in a stored brick
                VxTaps taps;
                if (occupied && (emits || !plain_albedo || surface_grid)) taps = vx_moved_taps(slot, s.brick, p, shift, here);
                vec3 le = vec3(0.0f);
                if (emits && here) le = vx_emission(taps) * (cut ? vx_cut_share(k + j, dt, t_cut) : 1.0f);
                if (sigma <= 0.0f && le.x + le.y + le.z <= 0.0f) continue;
                if (deep_on) vx_deep_span(deep, float(k + j) * dt * cos_forward, min(float(k + j + 1) * dt, t_cut) * cos_forward, T, vx_pixel_radiance(px), tau);
                // Exact integral of a constant segment: the light scattered in a segment of
                // extinction sigma is albedo * L_in * (T_k - T_k+1); emission integrates to
                // Le * (T_k - T_k+1) / sigma = Le * T_k * dt * (1 - e^(-sigma dt)) / (sigma dt),
                // the quotient by its series where sigma dt is small (thin smoke at a flame's
                // edge), where the difference of transmittances would lose its digits.
                tau = chunk.tau[j];
                float T_next = chunk.T[j];
                float absorbed = T - T_next;
                if (absorbed > 0.0f) {
                    vec3 x = origin + dir * t - shift;
                    vec3 albedo = plain_albedo || !here ? P.albedo : vx_albedo(taps);
                    VxLightingSample lit = vx_lighting_sample(x);
                    VxSurface surface = shaded_surface ? vx_surface(moving ? p - vx_to_index_dir(shift) : p) : vx_no_surface();
                    if (surface_grid && here) surface.weight *= vx_surface_weight_at(taps);
                    vec3 incident = vx_radiance_add(directional, vx_in_scattered(x, dir, per_sample_lights, lit, surface, P.anisotropy, VX_ALL_LINKS));
                    px.direct = vx_radiance_add(px.direct, albedo * incident * absorbed);
                    if (lit_indirect) px.indirect = vx_radiance_add(px.indirect, albedo * vx_lighting_indirect(lit, vx_light_block(VX_ALL_LINKS)) * absorbed);
                    px.ambient = vx_radiance_add(px.ambient, albedo * ambient * vx_lighting_ambient(lit) * absorbed);
                    depth_weighted += absorbed * t * cos_forward;
                }
                px.emission = vx_radiance_add(px.emission, le * (T * dt * vx_exp_integral(sigma * dt)));
                T = T_next;
            }
        }
        vx_dda_next(s, region, skips);
    }
    return vx_finish_ray(px, T, 1.0f - T, depth_weighted, deep);
}

// Ray i of pixel (x, y)'s P.time_samples (vx_pixel_ray).
VxPixel vx_render_ray(int x, int y, int i, VX_INOUT(VxDeepRay) deep) {
    vec3 origin;
    vec3 dir;
    vec3 forward;
    float time = vx_pixel_ray(x, y, i, origin, dir, forward);
    return vx_march_ray(origin, dir, forward, time, vx_holdout_distance(x, y, dir, forward), deep);
}

// Pixel (x, y): the mean of its rays. The GL backend dispatches ray by ray instead and averages
// with vx_pixel_mean_add on the host, which keeps each invocation as short as one ray's march.
VxPixel vx_render_pixel(int x, int y, VX_INOUT(VxDeepRay) deep) {
    VxPixel mean = vx_render_ray(x, y, 0, deep);
    float alpha_sum = mean.rgba.w;
    for (int i = 1; i < P.time_samples; ++i) vx_pixel_mean_add(mean, vx_render_ray(x, y, i, deep), i + 1, alpha_sum);
    return mean;
}
