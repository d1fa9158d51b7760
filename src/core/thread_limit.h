// How many cores a run uses: --threads N, else $VOXLUX_THREADS, else all the cores the process may
// run on (TBB reads the affinity mask a farm's scheduler sets). A farm gives a task N cores and
// expects it to use N, no more; the limit holds for every TBB loop (the march, the lighting, the
// reference, OpenVDB's own) and for Mesa's llvmpipe rasterizer threads (LP_NUM_THREADS, unless set).
// Costs nothing per frame: one tbb::global_control for the process's life.
#pragma once
#include <memory>
#include <optional>

#include <tbb/global_control.h>

namespace voxlux {

class ThreadLimit {
public:
    // `flag` is --threads as given. Throws InputError for a flag or $VOXLUX_THREADS below 1 or not a number.
    explicit ThreadLimit(std::optional<int> flag);
    // The limit in force, or 0 when all cores are used.
    int threads() const { return threads_; }
    // Whether LP_NUM_THREADS is this limit's (it was not set before): the viewer, which draws with
    // no rasterizer threads at all, may then replace it.
    static bool setRasterizerThreads();

private:
    int threads_ = 0;
    std::unique_ptr<tbb::global_control> control_;
};

}  // namespace voxlux
