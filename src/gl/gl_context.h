// Headless OpenGL 4.5 core context through EGL (no window, no surface), one per process.
#pragma once
#include <string>

namespace voxlux {

struct GlContextInfo {
    std::string renderer;   // GL_RENDERER
    bool software = false;  // llvmpipe, softpipe or SWR: a CPU rasteriser, not a GPU
    std::string display;    // the EGL display it runs on: "EGL device 0", "Mesa surfaceless platform", ...
};

// Creates the process's context on first use and makes it current on the calling thread (a context
// is current on one thread at a time, so GL work must not overlap across threads).
// Throws std::runtime_error with a one-line reason when no context can be created; the failure
// is remembered, so later calls throw the same reason without probing EGL again.
const GlContextInfo& ensureGlContext();

}  // namespace voxlux
