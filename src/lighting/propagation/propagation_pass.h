// One pass of the propagation method (Ropinski 2010, Sunden 2015): the sweeps a device runs
// (propagation_passes.h) through a grid of extinction into the illumination volume; its cost is one
// walk over the grid's slices, whatever the number of sweeps it carries.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_types.h"
#include "lighting/propagation/kernel/illumination_volume.h"

namespace voxlux {

// One pass of the propagation over a grid of extinction `sigma`: one or more sweeps along the same
// axis and direction, each carrying its own light (Sunden 2015's propagation group), each adding
// into the RGB block of `volume.values` that starts at `offset` plus its block_first (its light
// group's volume). The eye sweep is a pass of one sweep that replaces the indirect light with its
// result, reading the light before it from `input`; source sweeps read their sources from `input`.
struct PropagationPass {
    std::vector<kernel::VxPropParams> sweeps;       // same dims, axis and direction
    const kernel::VxParams* march = nullptr;        // noise and transport parameters
    const std::vector<float>* sigma = nullptr;      // the sweeps' dims cells (3 planes more: transport_planes)
    uint64_t sigma_generation = 0;                  // changes whenever *sigma does (0: unknown, a device keeps no copy)
    const std::vector<glm::vec4>* noise = nullptr;  // perturbation table (VX_NOISE_SIZE^3)
    size_t offset = 0;
    const std::vector<float>* input = nullptr;      // eye or source sweeps: 3 floats per cell
};

}  // namespace voxlux
