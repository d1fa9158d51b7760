#include "core/thread_limit.h"

#include <cstdlib>
#include <string>

#include "core/error.h"

namespace voxlux {
namespace {

bool set_rasterizer_threads = false;

}  // namespace

ThreadLimit::ThreadLimit(std::optional<int> flag) {
    if (flag && *flag < 1) throw InputError("--threads " + std::to_string(*flag) + ": must be 1 or more");
    if (!flag) {
        const char* env = std::getenv("VOXLUX_THREADS");
        if (!env || !*env) return;
        char* end = nullptr;
        const long n = std::strtol(env, &end, 10);
        if (*end != '\0' || n < 1 || n > 1 << 16)
            throw InputError("VOXLUX_THREADS='" + std::string(env) + "': expected a number of threads, 1 or more");
        flag = int(n);
    }
    threads_ = *flag;
    control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads_));
    if (!std::getenv("LP_NUM_THREADS")) {
        setenv("LP_NUM_THREADS", std::to_string(threads_).c_str(), 1);
        set_rasterizer_threads = true;
    }
}

bool ThreadLimit::setRasterizerThreads() { return set_rasterizer_threads; }

}  // namespace voxlux
