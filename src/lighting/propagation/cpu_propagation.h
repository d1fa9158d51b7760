// CPU backend of a propagation pass: the shared kernel (src/lighting/propagation/kernel/vx_propagation.h) slice after
// slice, each slice's rows in parallel (TBB). Every light of the pass has its own two 2D slice
// buffers (read the previous, write the current) and all of them add into the volume's slice
// together, as Sunden 2015's coherence-based propagation does: one walk over the extinction and
// the volume per pass, however many lights it carries.
#pragma once
#include <cstdint>
#include <vector>

#include "lighting/propagation/propagation_pass.h"

namespace voxlux {

// What the CPU keeps from one pass to the next. An x pass runs on slice-major copies of the
// extinction and of its result (cpu_propagation.cpp); kept here, their memory is allocated and its
// pages touched once rather than every pass, and a grid's extinction copy is made once for every x
// pass over it (by PropagationPass::sigma_generation: two slots, for the fine grid and the
// indirect light's own: chroma subsampled, or with per-material transport planes).
struct CpuSweepScratch {
    struct SlicedSigma {
        uint64_t generation = 0;   // PropagationPass::sigma_generation of the copy (0: none kept)
        uint64_t last_use = 0;
        std::vector<float> values;
    };
    SlicedSigma sigma[2];
    uint64_t uses = 0;
    std::vector<float> input, result;
};

void propagateCpu(const PropagationPass& pass, IlluminationVolume& volume, CpuSweepScratch& scratch);

}  // namespace voxlux
