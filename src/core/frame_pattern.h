// Frame numbers in paths: "fire_####.vdb" + 7 -> "fire_0007.vdb" (the run of # sets the padding).
#pragma once
#include <string>

namespace voxlux {

bool hasFramePattern(const std::string& path);
std::string expandFramePattern(const std::string& path, int frame);

}  // namespace voxlux
