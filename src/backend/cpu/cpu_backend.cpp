// CPU backend: the shared kernel with TBB, the march over 16x16 pixel tiles of the render region
// (the whole image without one), reading the march inputs through the kernel binding
// (src/kernel/cpu_kernel_data.cpp) the reference renderer and the light grid use too.
#include <tbb/blocked_range.h>
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
        img.pixels.assign(size_t(img.width) * img.height, k.vx_empty_pixel());   // outside the region, empty
        const glm::ivec4 region = in.region;
        if (in.params.deep_samples > 0) {
            marchDeep(k, img, region);
            return img;
        }
        tbb::parallel_for(tbb::blocked_range2d<int>(region.y, region.w, 16, region.x, region.z, 16),
                          [&](const tbb::blocked_range2d<int>& r) {
                              kernel::CpuKernel::VxDeepRay unused;
                              for (int y = r.rows().begin(); y < r.rows().end(); ++y)
                                  for (int x = r.cols().begin(); x < r.cols().end(); ++x)
                                      img.pixels[size_t(y) * img.width + x] = k.vx_render_pixel(x, y, unused);
                          });
        return img;
    }

private:
    // With deep samples, row by row: each row's samples are kept apart, then joined in order, so
    // memory follows the samples made, not the most a pixel may hold.
    static void marchDeep(kernel::CpuKernel& k, RenderImage& img, glm::ivec4 region) {
        std::vector<std::vector<kernel::VxDeepSample>> rows(size_t(img.height));
        img.deep.counts.resize(img.pixels.size());
        tbb::parallel_for(tbb::blocked_range<int>(region.y, region.w), [&](const tbb::blocked_range<int>& r) {
            kernel::CpuKernel::VxDeepRay ray;
            for (int y = r.begin(); y < r.end(); ++y)
                for (int x = region.x; x < region.z; ++x) {
                    const size_t i = size_t(y) * img.width + x;
                    img.pixels[i] = k.vx_render_pixel(x, y, ray);
                    img.deep.counts[i] = uint32_t(ray.count);
                    rows[size_t(y)].insert(rows[size_t(y)].end(), ray.s, ray.s + ray.count);
                }
        });
        for (auto& row : rows) {
            img.deep.samples.insert(img.deep.samples.end(), row.begin(), row.end());
            std::vector<kernel::VxDeepSample>().swap(row);
        }
    }
};

}  // namespace

std::unique_ptr<KernelBackend> makeCpuBackend() { return std::make_unique<CpuBackend>(); }

}  // namespace voxlux
