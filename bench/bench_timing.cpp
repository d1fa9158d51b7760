#include "bench_timing.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace voxlux::bench {

double seconds(const std::function<void()>& work) {
    const auto start = std::chrono::steady_clock::now();
    work();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double best(int repeats, const std::function<void()>& work) {
    double t = 1e30;
    for (int i = 0; i < repeats; ++i) t = std::min(t, seconds(work));
    return t;
}

double copyBandwidth() {
    const size_t n = size_t(64) << 20;   // floats: 256 MB per array
    std::vector<float> a(n, 1.0f), b(n, 2.0f);
    const double t = best(5, [&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
            std::copy(b.begin() + long(r.begin()), b.begin() + long(r.end()), a.begin() + long(r.begin()));
        });
    });
    return 2.0 * double(n) * sizeof(float) / t;
}

}  // namespace voxlux::bench
