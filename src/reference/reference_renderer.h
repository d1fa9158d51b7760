// Monte Carlo reference renderer (render.method "reference"), CPU only: unbiased volumetric path
// tracing of the same scene the march renders, to check the march and its approximations against.
// Free flights by delta tracking and shadow rays by ratio tracking, both against per-brick
// majorants; Henyey-Greenstein scattering with next-event estimation to the scene lights, up to
// max_bounces with Russian roulette; ambient light picked up by paths that escape; emission from
// the emission grids. Every per-sample quantity comes from the shared kernel (shaders/vx_*.h).
#pragma once
#include <cstdint>
#include <vector>

#include "kernel/kernel_backend.h"
#include "kernel/kernel_inputs.h"
#include "scene/scene.h"

namespace voxlux {

// Counter-based random numbers: number `dim` of sample `sample` of pixel `pixel` is a hash of the
// four, so results do not depend on thread scheduling and sample i is the same at any spp (more
// samples refine an image; they do not change the first ones).
class ReferenceRng {
public:
    ReferenceRng(uint32_t seed, uint32_t pixel, uint32_t sample);
    float next();  // uniform in [0, 1)

private:
    uint32_t key_;
    uint32_t dim_ = 0;
};

// The largest extinction (per world unit) anywhere in each atlas slot: the majorant of delta and
// ratio tracking there, from the density range of the blocks a sample there reads (the slot, and
// its neighbours under the tricubic filter) through the material (pbrt-v4's majorant grid at
// brick resolution). Emitting slots get at least one event per voxel, so their emission
// is sampled even where they do not attenuate.
std::vector<float> brickMajorants(const KernelInputs& inputs);

// Ratio-tracking estimate of the transmittance from world point x along unit direction w over
// distance `dist`: unbiased, one sample.
float ratioTrackedTransmittance(const KernelInputs& inputs, const std::vector<float>& majorants, glm::vec3 x,
                                glm::vec3 w, float dist, ReferenceRng& rng);

// Every pixel's sums over the samples taken so far, kept by an interactive render so that more
// samples continue an image rather than restart it: samples [samples, spp) added to the sums of
// [0, samples), one pixel's in order, give the sums a render of spp samples takes, so the image is
// the same bit for bit. Costs 144 bytes a pixel.
struct ReferenceSums {
    struct Pixel {
        glm::dvec3 direct{0.0}, indirect{0.0}, ambient{0.0}, emission{0.0};
        double transmittance = 0.0, depth = 0.0, lum = 0.0, lum2 = 0.0;
        int64_t events = 0;
        int hits = 0;
    };
    int samples = 0;   // per pixel
    int width = 0, height = 0;
    std::vector<Pixel> pixels;
};

// Renders inputs.params' camera with `settings.spp` paths per pixel centre. The pixel holds the
// beauty (premultiplied: alpha = 1 - the ratio-tracked transmittance of the camera ray), the
// direct (first-bounce NEE), indirect (the rest), ambient and emission (seen from the camera)
// AOVs, depth (mean distance of the first collision), samples (density lookups per path) and the
// variance of the pixel's luminance estimate (sample variance / spp). Throws InputError for the
// march-only effects surface and perturbation. Tracking stays bounded in any medium: a brick
// segment whose majorant overflows a float (density 3e38), or that takes over 2^16 tentative
// collisions, is taken as opaque there; `opaque_segments`, when given, receives their count.
// With `sums` of the same image size and fewer samples, only the missing samples are taken and
// added to them; otherwise they are started again (the caller keeps them only while nothing but
// the sample count changes).
RenderImage renderReference(const KernelInputs& inputs, const ReferenceSettings& settings,
                            uint64_t* opaque_segments = nullptr, ReferenceSums* sums = nullptr);

}  // namespace voxlux
