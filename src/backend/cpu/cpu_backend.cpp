// CPU backend: the shared kernel with TBB, the march over 16x16 pixel tiles. The lighting
// methods' CPU passes (cpu_light_pass.cpp, cpu_propagation.cpp) and the grade stage's colour
// transforms (cpu_color_transform.cpp) use the same kernel binding.
#include <cstdio>
#include <cstdlib>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "kernel/cpu_kernel.h"
#include "kernel/kernel_backend.h"

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

[[noreturn]] void kernel::vx_bounds_trap(const char* what, int index, int size) {
    std::fprintf(stderr, "voxlux: kernel %s index %d outside [0, %d)\n", what, index, size);
    std::abort();
}

kernel::CpuKernel bindCpuKernel(const KernelInputs& in) {
    kernel::CpuKernel k;
    k.P = in.params;
    k.density = in.atlas->density;
    k.emission = in.atlas->emission;
    k.color = in.atlas->color;
    k.page = in.pages->entries;
    k.lights = in.lights;
    k.tf_lut = in.tf_lut;
    k.emission_lut = in.emission_lut;
    if (in.light_cache) k.cache = in.light_cache->values;
    if (in.illumination) k.illum = in.illumination->values;
    k.noise = in.noise;
    return k;
}

std::unique_ptr<KernelBackend> makeCpuBackend() { return std::make_unique<CpuBackend>(); }

}  // namespace voxlux
