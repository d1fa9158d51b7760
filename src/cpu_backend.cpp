// CPU backend: the shared kernel run over 16x16 pixel tiles with TBB.
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "cpu_kernel.h"
#include "kernel_backend.h"
#include "summed_volume.h"

namespace voxlux {
namespace {

class CpuBackend final : public KernelBackend {
public:
    std::string name() const override { return "cpu"; }

    RenderImage march(const KernelInputs& in) override {
        kernel::CpuKernel k = bindCpuKernel(in);
        RenderImage img;
        img.width = int(in.params.camera_frame.z);
        img.height = int(in.params.camera_frame.w);
        img.pixels.resize(size_t(img.width) * img.height);
        tbb::parallel_for(tbb::blocked_range2d<int>(0, img.height, 16, 0, img.width, 16),
                          [&](const tbb::blocked_range2d<int>& r) {
                              for (int y = r.rows().begin(); y < r.rows().end(); ++y)
                                  for (int x = r.cols().begin(); x < r.cols().end(); ++x)
                                      img.pixels[size_t(y) * img.width + x] = k.vx_render_pixel(x, y);
                          });
        return img;
    }

    void scanSat(SummedVolume& sat) override { scanSummedVolume(sat); }

    void fillLightChannel(const LightPass& pass, LightCache& cache) override {
        kernel::CpuKernel k;
        k.S = pass.params;
        k.sat = pass.sat->words.data();
        k.lights = pass.lights->data();
        const glm::ivec3 d = pass.params.dims;
        const int light = pass.params.pass.x, channel = pass.params.pass.y, plane = int(pass.params.shells.w);
        const uint8_t* needed = pass.needed->data();
        tbb::parallel_for(tbb::blocked_range2d<int>(0, d.z, 1, 0, d.y, 8), [&](const tbb::blocked_range2d<int>& r) {
            for (int z = r.rows().begin(); z < r.rows().end(); ++z)
                for (int y = r.cols().begin(); y < r.cols().end(); ++y)
                    for (int x = 0; x < d.x; ++x) {
                        const size_t i = (size_t(z) * d.y + y) * d.x + x;
                        if (!needed[i]) continue;
                        const glm::ivec3 c(x, y, z);
                        cache.values[i * cache.channels + channel] =
                            light < 0 ? k.vx_ambient_tau(c, plane) : k.vx_cone_tau(c, k.vx_light(light));
                    }
        });
    }
};

}  // namespace

kernel::CpuKernel bindCpuKernel(const KernelInputs& in) {
    kernel::CpuKernel k;
    k.P = in.params;
    k.density = in.atlas->density.data();
    k.emission = in.atlas->emission.data();
    k.color = in.atlas->color.data();
    k.page = in.pages->entries.data();
    k.lights = in.lights.data();
    k.tf_lut = in.tf_lut.data();
    k.cache = in.cache;
    return k;
}

std::unique_ptr<KernelBackend> makeCpuBackend() { return std::make_unique<CpuBackend>(); }

}  // namespace voxlux
