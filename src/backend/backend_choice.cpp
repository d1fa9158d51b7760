#include "backend/backend_choice.h"

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
