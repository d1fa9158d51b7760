// Reads back the RGBA of an EXR that voxlux wrote (the ground truth `voxlux study` keeps between
// runs, and tests), and one channel of any EXR (a CG render's depth, for a holdout).
#pragma once
#include <string>
#include <vector>

#include "kernel/kernel_backend.h"

namespace voxlux {

// R, G, B and A of the data window as float (missing channels read as 0); the other pixel
// fields stay 0. Throws InputError "<path>: ..." when the file cannot be read.
RenderImage readExrRgba(const std::string& path);

// One channel of an EXR's display window (the frame) as float, row 0 at the top: an auto-cropped
// data window leaves `outside` in the pixels it does not cover, and overscan past the frame is
// left out.
struct ExrChannel {
    int width = 0;
    int height = 0;
    std::vector<float> values;
};
// Throws InputError "<path>: ..." when the file cannot be read or has no channel `name` (the
// message lists the channels it has).
ExrChannel readExrChannel(const std::string& path, const std::string& name, float outside = 0.0f);

}  // namespace voxlux
