// Emission lights the medium: fire and explosions illuminate their own smoke. The emitted radiance
// per world unit, box-filtered into the indirect light's grid, is a source inside the
// illumination volume, swept through the grid from the six axis directions (the sphere split into
// the six faces of a cube, a sixth of 4 pi each; each face's light blurred over the indirect cone
// as it goes). Source iteration, as in transport theory: order 1 sweeps the emission, attenuated
// by the extinction, into phi_1, the fluence of light emitted and not yet scattered (what of it
// reaches the camera directly is the march's emission term); its scattered light, albedo *
// sigma_t * phi_1 / (4 pi) per world unit, is order 2's source, swept the same way into phi_2.
// The orders after are the geometric series phi_2 (r + r^2 + ...), r = phi_2 / phi_1 per cell and
// channel, at most the albedo. All add into the indirect block, which the march scatters as it
// does the lights' indirect light.
// Limits (measured in docs/accuracy.md): a sweep carries radiance along its axis with no
// geometric spreading, so far from a small source it stays brighter than the 1 / r^2 it should
// fall off by; deep in an optically thick medium the series ends too soon (light that needs many
// scatterings to get out); the inner orders scatter with the material's constant albedo (a
// colour grid tints only the march's last scattering), of several volumes with each cell's mix.
// Cost: 12 RGB sweeps over the indirect grid, on an entire update only (emission does not change
// when a light does).
#pragma once
#include "lighting/propagation/propagation_stages.h"

namespace voxlux {

// Whether the fast path lights the medium with its emission: the scene emits, and the march
// carries propagated indirect light.
bool emissionLightsTheMedium(const Scene& scene);

// The source sweeps addEmittedLight runs: two orders, each from the six axis directions.
constexpr int kEmittedLightSweeps = 12;

// What addEmittedLight costs on `grid` (none without emission), in the units of the propagation's
// cost estimate (SweepCost): each source sweep an indirect sweep in a pass of its own.
double emittedLightCost(const SweepGrid& grid);

// Adds the fluence of the emission in `grid` (its `emission`, on the indirect light's grid) into
// the indirect block of the group volume of `volume` that starts at float `block_first`. `indirect` holds the indirect sweeps' grid and blur. The
// orders after the first scatter with `material`'s albedo, or the grid's `scattering` if it has one.
void addEmittedLight(const SweepGrid& grid, const Material& material, const kernel::VxPropParams& indirect,
                     const KernelInputs& inputs, PropagationPasses& device, size_t block_first, IlluminationVolume& volume, LightUpdate& report);

}  // namespace voxlux
