// What a CPU-only build (cmake -DVOXLUX_GL=OFF, for farm nodes without EGL) has in place of the GL
// backend: asking for it is an input error that says how the build was made.
#include "core/error.h"
#include "backend/backend_choice.h"

namespace voxlux {

std::unique_ptr<KernelBackend> makeGlBackend() {
    throw InputError("render.backend \"gl\": this voxlux was built without the GL backend (VOXLUX_GL=OFF); use \"cpu\"");
}

bool hardwareGlAvailable() { return false; }

}  // namespace voxlux
