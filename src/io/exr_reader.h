// Reads back the RGBA of an EXR that voxlux wrote: the ground truth `voxlux study` keeps between
// runs, and tests.
#pragma once
#include <string>

#include "kernel/kernel_backend.h"

namespace voxlux {

// R, G, B and A of the data window as float (missing channels read as 0); the other pixel
// fields stay 0. Throws InputError "<path>: ..." when the file cannot be read.
RenderImage readExrRgba(const std::string& path);

}  // namespace voxlux
