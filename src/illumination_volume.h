// The illumination volume (Ropinski 2010): per cell of a dense grid over the occupied bricks, the
// direct luminance that reaches it through the medium and, with indirect light, the blurred,
// transport-attenuated RGB radiance (Kniss 2003), possibly on a grid coarser by the chroma
// subsampling factor. Every light sweep adds its weighted light, so several lights and both
// blend axes share one volume.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "kernel_types.h"

namespace voxlux {

struct IlluminationVolume {
    glm::ivec3 dims{0};             // luminance cells
    int chroma = 1;                 // chroma subsampling factor: indirect cells are chroma^3 luminance cells
    glm::ivec3 chroma_dims{0};      // indirect cells (0 without indirect light)
    glm::mat4 world_to_illum{1.0f}; // world -> luminance-cell coordinates
    std::vector<float> values;      // luminance per cell, then 3 floats per indirect cell

    size_t cells() const { return size_t(dims.x) * dims.y * dims.z; }
    size_t chromaCells() const { return size_t(chroma_dims.x) * chroma_dims.y * chroma_dims.z; }
    size_t indirectOffset() const { return cells(); }
};

// One sweep of the propagation (VxPropParams) over a grid of extinction `sigma`, writing the block
// of `volume.values` that starts at `offset`: a light sweep adds its weighted light there, the eye
// sweep replaces the indirect light with its result, reading the light before it from `input`.
struct SweepJob {
    kernel::VxPropParams params{};
    const kernel::VxParams* march = nullptr;        // noise and transport parameters
    const std::vector<float>* sigma = nullptr;      // params.dims cells
    const std::vector<glm::vec4>* noise = nullptr;  // perturbation table (VX_NOISE_SIZE^3)
    size_t offset = 0;
    const std::vector<float>* input = nullptr;      // eye sweep only: 3 floats per cell
};

}  // namespace voxlux
