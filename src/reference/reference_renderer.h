// Monte Carlo reference renderer (render.method "reference"), CPU only: unbiased volumetric path
// tracing of the same scene the march renders, to check the march and its approximations against.
// The camera ray is ratio-tracked to the end of the volume once, and that one pass gives its
// transmittance, the emission it sees and a first scattering point chosen among its tentative
// collisions with the probability of scattering as weight, so no path escapes empty-handed.
// Later flights are delta tracked (the last one a path may take ratio tracked) and shadow rays
// residual-ratio tracked, against per-brick majorants and minorants. Henyey-Greenstein scattering with next-event estimation to the scene
// lights, up to max_bounces with Russian roulette; ambient light picked up by paths that escape;
// emission from the emission grids. Every per-sample quantity comes from the shared kernel
// (shaders/vx_*.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "kernel/kernel_backend.h"
#include "kernel/kernel_inputs.h"
#include "reference/sample_sequence.h"
#include "scene/scene.h"

namespace voxlux {

// The largest and smallest extinction (per world unit) anywhere in each atlas slot, from the
// density range of the blocks a sample there reads (the slot, and its neighbours under the
// tricubic filter) through the material (pbrt-v4's majorant grid at brick resolution). The
// majorant sets the rate of tentative collisions; the minorant is residual ratio tracking's
// control extinction. Emitting slots get a majorant of at least one event per voxel, so their
// emission is sampled even where they do not attenuate.
// Of several volumes (shaders/vx_volumes.h), a majorant per volume instead: its largest
// extinction, summed where their boxes overlap.
struct ExtinctionBounds {
    std::vector<float> majorant, minorant;  // per slot
    std::vector<float> volume_majorant;     // per volume, of several
};
ExtinctionBounds brickExtinctionBounds(const KernelInputs& inputs);

// Residual ratio-tracking estimate of the transmittance from world point x along unit direction
// w over distance `dist`: unbiased, one sample.
float ratioTrackedTransmittance(const KernelInputs& inputs, const ExtinctionBounds& bounds, glm::vec3 x, glm::vec3 w,
                                float dist, ReferenceRng& rng);

// Every pixel's sums over the samples taken so far, kept by an interactive render so that more
// samples continue an image rather than restart it: samples [samples, spp) added to the sums of
// [0, samples), one pixel's in order, give the sums a render of spp samples takes, so the image is
// the same bit for bit. Costs 144 bytes a pixel, and 24 a light-group layer.
struct ReferenceSums {
    struct Pixel {
        glm::dvec3 direct{0.0}, indirect{0.0}, ambient{0.0}, emission{0.0};
        double transmittance = 0.0, depth = 0.0, scatter_weight = 0.0, lum = 0.0, lum2 = 0.0;
        int64_t events = 0;
    };
    int samples = 0;   // per pixel
    int width = 0, height = 0;
    std::vector<Pixel> pixels;
    std::vector<glm::dvec3> layers;   // with light groups, each pixel's layers (as RenderImage::light_groups)
};

// Renders inputs.params' camera with `settings.spp` paths per pixel centre. The pixel holds the
// beauty (premultiplied: alpha = 1 - the ratio-tracked transmittance of the camera ray), the
// direct (first-bounce NEE), indirect (the rest), ambient and emission (seen from the camera)
// AOVs, depth (mean distance of the first scattering, weighted by the probability of scattering),
// samples (density lookups per path) and the variance of the pixel's luminance estimate (sample
// variance / spp). Throws InputError for the march-only effects surface and perturbation. Tracking stays bounded in any medium: a brick
// segment whose majorant overflows a float (density 3e38), or that takes over 2^16 tentative
// collisions, is taken as opaque there; `opaque_segments`, when given, receives their count.
// With `sums` of the same image size and fewer samples, only the missing samples are taken and
// added to them; otherwise they are started again (the caller keeps them only while nothing but
// the sample count changes).
// With `light_groups` (lightGroups' names), the image's light_groups are each path's
// contributions by the group of the light they came from, and the emitted light's: the same
// samples as the beauty, so they sum to it.
RenderImage renderReference(const KernelInputs& inputs, const ReferenceSettings& settings,
                            uint64_t* opaque_segments = nullptr, ReferenceSums* sums = nullptr,
                            const std::vector<std::string>& light_groups = {});

}  // namespace voxlux
