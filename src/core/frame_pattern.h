// Frame numbers in paths: "fire_####.vdb" + 7 -> "fire_0007.vdb" (the run of # sets the padding).
#pragma once
#include <string>

#include "core/frame_set.h"

namespace voxlux {

bool hasFramePattern(const std::string& path);
std::string expandFramePattern(const std::string& path, int frame);

// The frames of `pattern` (#### in its file name) whose files exist, in order, from one listing
// of its folder: a name is a frame when expandFramePattern gives it back. Empty when none does.
FrameSet framesOnDisk(const std::string& pattern);

}  // namespace voxlux
