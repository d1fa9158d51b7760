#include "core/frame_pattern.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

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

FrameSet framesOnDisk(const std::string& pattern, const FrameSet& candidates) {
    namespace fs = std::filesystem;
    const fs::path path(pattern);
    const std::string name = path.filename().string();
    const size_t first = name.find('#'), last = name.find_last_of('#');
    FrameSet frames;
    std::error_code ec;
    if (first == std::string::npos) {   // the frame number is in a folder's name: no one listing holds them
        if (candidates.count() > kMostFramesLookedUp)
            throw std::invalid_argument("frames " + candidates.text() + ": more than " + std::to_string(kMostFramesLookedUp) +
                                        " to look up one by one (#### is in a folder's name)");
        for (int64_t k = 0; k < candidates.count(); ++k)
            if (fs::exists(expandFramePattern(pattern, candidates.at(k)), ec)) frames.add(candidates.at(k));
        return frames;
    }
    const std::string prefix = name.substr(0, first), suffix = name.substr(last + 1);
    std::vector<int> found;
    for (const auto& entry : fs::directory_iterator(path.parent_path().empty() ? fs::path(".") : path.parent_path(), ec)) {
        const std::string file = entry.path().filename().string();
        if (file.size() <= prefix.size() + suffix.size() || file.rfind(prefix, 0) != 0 ||
            file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        const std::string number = file.substr(prefix.size(), file.size() - prefix.size() - suffix.size());
        if (number.size() > 10 || number.find_first_not_of("-0123456789") != std::string::npos) continue;
        const long frame = std::strtol(number.c_str(), nullptr, 10);
        if (expandFramePattern(name, int(frame)) == file) found.push_back(int(frame));
    }
    std::sort(found.begin(), found.end());
    for (int f : found) frames.add(f);
    return frames;
}

}  // namespace voxlux
