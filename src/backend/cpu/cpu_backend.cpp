// CPU backend: the shared kernel with TBB, the march over 16x16 pixel tiles, reading the march
// inputs through the kernel binding (src/kernel/cpu_kernel.cpp) the reference renderer and the
// light grid use too.
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "backend/backend_choice.h"
#include "kernel/cpu_kernel.h"

namespace voxlux {
namespace {

class CpuBackend final : public KernelBackend {
public:
    std::string name() const override { return "cpu"; }
    Device device() const override { return Device::Cpu; }

    RenderImage march(const KernelInputs& in) override {
        kernel::CpuKernel k = bindCpuKernel(in);
        RenderImage img;
        img.width = in.params.width;
        img.height = in.params.height;
        img.pixels.resize(size_t(img.width) * img.height);
        tbb::parallel_for(tbb::blocked_range2d<int>(0, img.height, 16, 0, img.width, 16),
                          [&](const tbb::blocked_range2d<int>& r) {
                              for (int y = r.rows().begin(); y < r.rows().end(); ++y)
                                  for (int x = r.cols().begin(); x < r.cols().end(); ++x)
                                      img.pixels[size_t(y) * img.width + x] = k.vx_render_pixel(x, y);
                          });
        return img;
    }
};

}  // namespace

std::unique_ptr<KernelBackend> makeCpuBackend() { return std::make_unique<CpuBackend>(); }

}  // namespace voxlux
