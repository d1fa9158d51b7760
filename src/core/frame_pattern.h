// Frame numbers in paths: "fire_####.vdb" + 7 -> "fire_0007.vdb" (the run of # sets the padding).
#pragma once
#include <string>

#include "core/frame_set.h"

namespace voxlux {

bool hasFramePattern(const std::string& path);
std::string expandFramePattern(const std::string& path, int frame);

// The frames of `pattern` whose files exist, in order: with #### in the file name, from one
// listing of its folder (a name is a frame when expandFramePattern gives it back), whatever
// `candidates` says; with #### in a folder's name, those of `candidates` whose file exists, looked
// up one by one (std::invalid_argument past kMostFramesLookedUp). Empty when none does.
inline constexpr int64_t kMostFramesLookedUp = 100000;
FrameSet framesOnDisk(const std::string& pattern, const FrameSet& candidates);

}  // namespace voxlux
