// The GL backend against the CPU backend: both render a scene through the whole render graph on
// the same synthetic volume (a box of constant density crossing the origin, beside a sphere of
// smooth noise, with an emission and a colour grid), and every AOV is compared. Both run the one
// kernel source (shaders/vx_*.h), so the images may differ only by float rounding: the GPU's
// exp/log/sqrt, and where each compiler fuses multiply-adds. The backends' own tests
// (tests/backend/gl/test_gl_backend.cpp) and each lighting method's (tests/lighting/<method>/)
// use these.
#pragma once
#include <array>
#include <cstddef>

#include <openvdb/openvdb.h>

#include "kernel/kernel_backend.h"
#include "scene/scene.h"
#include "volume/vdb_loader.h"

namespace voxlux::test::gl_agreement {

// With `emission_and_color`, an emission grid (the scene's one source, emissionSource()) and a
// colour grid over the sphere.
LoadedVolume makeVolume(bool emission_and_color);
// A second emission grid, over part of the box: a topology of its own.
openvdb::FloatGrid::Ptr flameGrid();
EmissionSource emissionSource();
Light directionalLight();
Light pointLight();   // just inside the sphere's edge, facing the box
Light spotLight();
// 74 x 66 pixels (not a multiple of the 8x8 work group, more rows than one GL band), ray-marched
// shadows, a directional and a point light.
Scene baseScene();

struct Renders {
    RenderImage cpu, gl;
};
// Both backends on the same volume, each through the whole render graph, as a render on it would
// run: each builds its own light cache and illumination volume. The camera is the default framing
// moved in, so the volume reaches the image's edges and every dispatch band has something to get
// wrong.
Renders renderBoth(LoadedVolume volume, Scene scene, KernelBackend& gl);

// AOV channels as float ranges of VxPixel (rgba, direct, ambient, emission, indirect, transmittance,
// depth; the trailing sample count is a cost, not an image, and is not compared).
// Depth is an opacity-weighted mean, a ratio of two tiny numbers where alpha is tiny (alpha 4e-6
// turns a 1-ulp difference in T into 3e-3 of depth), so it is compared where alpha >= 1e-3 only.
struct Channel {
    const char* name;
    int first, count;
    float min_alpha;
};
enum ChannelId { kRgba, kDirect, kAmbient, kEmission, kIndirect, kTransmittance, kDepth, kChannelCount };
constexpr Channel kChannels[kChannelCount] = {{"rgba", 0, 4, 0.0f},
                                              {"direct", 4, 3, 0.0f},
                                              {"ambient", 7, 3, 0.0f},
                                              {"emission", 10, 3, 0.0f},
                                              {"indirect", 13, 3, 0.0f},
                                              {"transmittance", 16, 1, 0.0f},
                                              {"depth", 17, 1, 1e-3f}};
static_assert(offsetof(kernel::VxPixel, indirect) == 13 * sizeof(float) &&
              offsetof(kernel::VxPixel, transmittance) == 16 * sizeof(float) &&
              offsetof(kernel::VxPixel, depth) == 17 * sizeof(float));

// Tolerances, relative to the CPU channel's scale. The backends differ only by float rounding
// (log/sqrt implementations, FMA contraction). Measured on llvmpipe: RMSE <= 1.5e-6 of the mean,
// max abs <= 4.1e-6 of the peak (each run prints them). 1e-4 leaves room for that and for a GPU's
// approximate log/sqrt, while a sample taken by one backend and skipped by the other at a brick
// boundary (~1e-2) still fails.
constexpr double kRmseOfMean = 1e-4;
constexpr double kMaxAbsOfPeak = 1e-4;

struct ChannelStats {
    double rmse = 0.0, max_abs = 0.0;  // GL - CPU
    double mean = 0.0, peak = 0.0;     // of |CPU|
};

// Checks every channel against the tolerances (printing the measured agreement, which
// docs/architecture.md quotes) and returns the statistics for further checks.
std::array<ChannelStats, kChannelCount> expectMatch(const Renders& r);

}  // namespace voxlux::test::gl_agreement
