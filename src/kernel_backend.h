// Kernel backends: the SAT scan, the light passes, the propagation sweeps and the march, each running the shared kernel
// (shaders/vx_*.h) on the CPU (TBB) or as GL compute shaders.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "illumination_volume.h"
#include "kernel_inputs.h"
#include "light_cache.h"
#include "light_grid.h"

#include <OpenColorIO/OpenColorIO.h>

namespace voxlux {

struct RenderImage {
    int width = 0;
    int height = 0;
    std::vector<kernel::VxPixel> pixels;   // row-major, row 0 at the top
};

class KernelBackend {
public:
    virtual ~KernelBackend() = default;
    virtual std::string name() const = 0;   // "cpu" or "gl (<renderer>)"
    virtual RenderImage march(const KernelInputs& inputs) = 0;
    // The SAT of a light grid, reusing `sat`'s storage; both backends give the same integers.
    virtual void buildSat(const LightGrid& grid, SummedVolume& sat) = 0;
    // One light-cache channel (see LightPass).
    virtual void fillLightChannel(const LightPass& pass, LightCache& cache) = 0;
    // One propagation pass (see PropagationPass) into `volume`.
    virtual void propagate(const PropagationPass& pass, IlluminationVolume& volume) = 0;
    // Applies an OCIO processor in place to premultiplied RGBA pixels (grade stage). With
    // `unpremultiply`, colour is divided by alpha where alpha > 0 and multiplied back after
    // (shaders/vx_grade.h); alpha is never changed. cpu: OCIO's CPU processor; gl: the
    // processor's generated GLSL and LUT textures.
    virtual void transformColors(const OCIO_NAMESPACE::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                                 bool unpremultiply) = 0;
};

std::unique_ptr<KernelBackend> makeCpuBackend();

// Throws std::runtime_error when no OpenGL 4.5 context can be created (EGL, headless).
std::unique_ptr<KernelBackend> makeGlBackend();

// True when an EGL context exists and runs on a hardware GPU (not llvmpipe/softpipe).
bool hardwareGlAvailable();

// Picks the backend for `choice`: Auto means GL on a hardware GPU, else CPU.
std::unique_ptr<KernelBackend> makeBackend(Backend choice);

}  // namespace voxlux
