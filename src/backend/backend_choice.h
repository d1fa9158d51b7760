// The march's backends and the choice between them: `auto` prefers a hardware GPU and falls back
// to the TBB CPU backend, which beats Mesa's software rasteriser (llvmpipe) on every stage.
#pragma once
#include <memory>

#include "kernel/kernel_backend.h"

namespace voxlux {

std::unique_ptr<KernelBackend> makeCpuBackend();

// Throws std::runtime_error when no OpenGL 4.5 context can be created (EGL, headless).
std::unique_ptr<KernelBackend> makeGlBackend();

// True when an EGL context exists and runs on a hardware GPU (not llvmpipe/softpipe).
bool hardwareGlAvailable();

// Picks the backend for `choice`: Auto means GL on a hardware GPU, else CPU.
std::unique_ptr<KernelBackend> makeBackend(Backend choice);

}  // namespace voxlux
