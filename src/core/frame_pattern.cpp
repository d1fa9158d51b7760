#include "core/frame_pattern.h"

#include <cstdio>

namespace voxlux {

bool hasFramePattern(const std::string& path) { return path.find('#') != std::string::npos; }

std::string expandFramePattern(const std::string& path, int frame) {
    const size_t first = path.find('#');
    if (first == std::string::npos) return path;
    size_t last = first;
    while (last + 1 < path.size() && path[last + 1] == '#') ++last;
    char digits[32];
    std::snprintf(digits, sizeof digits, "%0*d", int(last - first + 1), frame);
    return path.substr(0, first) + digits + path.substr(last + 1);
}

}  // namespace voxlux
