#include "bench_timing.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>

#include "render/renderer.h"

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

double TimedRender::operator()(const std::string& stage) const {
    auto it = seconds.find(stage);
    return it == seconds.end() ? 0.0 : it->second;
}

TimedRender renderFresh(const Scene& scene, int runs) {
    TimedRender r;
    for (int run = 0; run < runs; ++run) {
        FrameResult f = Renderer(scene).render(std::nullopt, false);
        for (const auto& [stage, t] : f.stage_seconds) {
            auto [it, first] = r.seconds.emplace(stage, t);
            if (!first) it->second = std::min(it->second, t);
        }
        r.image = std::move(f.image);
    }
    return r;
}

bool parseOptions(int argc, char** argv, const char* program, const std::string& default_data, Options& o) {
    o.data = default_data;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--data") && i + 1 < argc) o.data = argv[++i];
        else if (!std::strcmp(argv[i], "--paper-only")) o.sweeps = false;
        else if (!std::strcmp(argv[i], "--sweeps-only")) o.paper = false;
        else if (!std::strcmp(argv[i], "--svg") && i + 1 < argc) o.svg = argv[++i];
        else if (!std::strcmp(argv[i], "--quick")) o.quick = true;
        else {
            std::fprintf(stderr, "usage: %s [--data DIR] [--svg FILE] [--quick] [--paper-only | --sweeps-only]\n", program);
            return false;
        }
    }
    return true;
}

}  // namespace voxlux::bench
