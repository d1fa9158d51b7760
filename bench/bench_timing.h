// Wall-clock helpers shared by the benchmarks: timing a piece of work, the best of several runs,
// and a STREAM-style copy bandwidth to set memory-bound passes against.
#pragma once
#include <functional>

namespace voxlux::bench {

// Wall-clock seconds `work` takes.
double seconds(const std::function<void()>& work);

// The fastest of `repeats` runs of `work`, seconds.
double best(int repeats, const std::function<void()>& work);

// STREAM "copy": a[i] = b[i] over two 256 MB float arrays (far larger than the caches), all
// threads, best of 5; bytes per second counting the read and the write.
double copyBandwidth();

}  // namespace voxlux::bench
