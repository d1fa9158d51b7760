// March stage backends. Both run the same kernel (shaders/vx_march.h) over every pixel.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "kernel_inputs.h"

namespace voxlux {

struct RenderImage {
    int width = 0;
    int height = 0;
    std::vector<kernel::VxPixel> pixels;   // row-major, row 0 at the top
};

class MarchBackend {
public:
    virtual ~MarchBackend() = default;
    virtual std::string name() const = 0;   // "cpu" or "gl (<renderer>)"
    virtual RenderImage march(const KernelInputs& inputs) = 0;
};

std::unique_ptr<MarchBackend> makeCpuBackend();

// Throws std::runtime_error when no OpenGL 4.5 context can be created (EGL, headless).
std::unique_ptr<MarchBackend> makeGlBackend();

// True when an EGL context exists and runs on a hardware GPU (not llvmpipe/softpipe).
bool hardwareGlAvailable();

// Picks the backend for `choice`: Auto means GL on a hardware GPU, else CPU.
std::unique_ptr<MarchBackend> makeBackend(Backend choice);

}  // namespace voxlux
