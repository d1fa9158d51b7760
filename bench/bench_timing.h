// What the benchmarks share: timing a piece of work, the best of several runs, a STREAM-style
// copy bandwidth to set memory-bound passes against, a render's stage times, and the command line.
#pragma once
#include <functional>
#include <map>
#include <string>

#include "kernel/kernel_backend.h"
#include "scene/scene.h"

namespace voxlux::bench {

// Wall-clock seconds `work` takes.
double seconds(const std::function<void()>& work);

// The fastest of `repeats` runs of `work`, seconds.
double best(int repeats, const std::function<void()>& work);

// STREAM "copy": a[i] = b[i] over two 256 MB float arrays (far larger than the caches), all
// threads, best of 5; bytes per second counting the read and the write.
double copyBandwidth();

// A scene rendered several times on fresh renderers (nothing reused).
struct TimedRender {
    std::map<std::string, double> seconds;   // the fastest time of each stage over the runs
    RenderImage image;                       // of the last run
    double operator()(const std::string& stage) const;   // 0 for a stage that did not run
};
TimedRender renderFresh(const Scene& scene, int runs);

// The benchmarks' command line: [--data DIR] [--svg FILE] [--quick] [--paper-only | --sweeps-only].
struct Options {
    std::string data;          // the shared test data (default: ../shared/data beside the sources)
    std::string svg;           // where to write the error-against-time plot, if anywhere
    bool quick = false;
    bool paper = true;         // the synthetic comparison with the paper
    bool sweeps = true;        // the knob sweeps on real caches
};
// False (after printing the usage for `program`) on an unknown argument.
bool parseOptions(int argc, char** argv, const char* program, const std::string& default_data, Options& out);

}  // namespace voxlux::bench
