// Backend selection: `auto` prefers a hardware GPU and falls back to the TBB CPU backend, which
// beats Mesa's software rasteriser (llvmpipe) on every stage.
#include "kernel/kernel_backend.h"

namespace voxlux {

std::unique_ptr<KernelBackend> makeBackend(Backend choice) {
    switch (choice) {
        case Backend::Cpu: return makeCpuBackend();
        case Backend::Gl: return makeGlBackend();
        case Backend::Auto: return hardwareGlAvailable() ? makeGlBackend() : makeCpuBackend();
    }
    return makeCpuBackend();
}

}  // namespace voxlux
