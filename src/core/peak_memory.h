// The process's peak resident memory, as --stats reports it.
#pragma once
#include <sys/resource.h>

#include <cstddef>

namespace voxlux {

inline size_t peakRssBytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return size_t(u.ru_maxrss) * 1024;   // Linux reports KiB
}

}  // namespace voxlux
