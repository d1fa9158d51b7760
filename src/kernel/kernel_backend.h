// Kernel backends: the march, running the shared kernel (shaders/vx_*.h) on the CPU (TBB) or as
// a GL compute shader, and the device a render runs on. The lighting methods' passes and the
// grade's colour transforms are their own interfaces on the same device (sat_passes.h,
// propagation_passes.h, color_transformer.h), made per device by the stage that runs them, so
// adding a method never changes this interface.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "kernel/kernel_inputs.h"

namespace voxlux {

// Deep samples of an image (output.deep; shaders/vx_deep.h), pixel by pixel in the pixels' order,
// each pixel's front to back.
struct DeepSamples {
    std::vector<uint32_t> counts;                  // per pixel; empty: no deep output
    std::vector<kernel::VxDeepSample> samples;
};

// One layer of output.aovs "light_groups": the light one group brings to the beauty, per pixel as
// RenderImage::pixels.
struct LightGroupLayer {
    std::string name;                      // lightgroup.<name>
    std::vector<glm::vec3> rgb;
};

struct RenderImage {
    int width = 0;
    int height = 0;
    std::vector<kernel::VxPixel> pixels;   // row-major, row 0 at the top
    DeepSamples deep;
    std::vector<LightGroupLayer> light_groups;   // the scene's light groups, then "emission": they sum
                                                 // to the beauty's colour (empty unless asked for)
};

enum class Device { Cpu, Gl };

class KernelBackend {
public:
    virtual ~KernelBackend() = default;
    virtual std::string name() const = 0;   // "cpu" or "gl (<renderer>)"
    virtual Device device() const = 0;
    virtual RenderImage march(const KernelInputs& inputs) = 0;
};

// A stage's passes of one kind on the device of the backend it runs with, made the first time and
// again when the device changes (`render.backend` edited between frames).
template <class Passes>
class OnDevice {
public:
    using Factory = std::unique_ptr<Passes> (*)(Device);
    explicit OnDevice(Factory make) : make_(make) {}

    Passes& on(const KernelBackend& backend) {
        if (!passes_ || device_ != backend.device()) {
            passes_ = make_(backend.device());
            device_ = backend.device();
        }
        return *passes_;
    }
    // Drops the passes and what they keep between runs (device buffers, scratch copies).
    void release() { passes_.reset(); }
    // Drops them when the data they keep copies of changes, named by its `generation`.
    void keepFor(uint64_t generation) {
        if (generation != kept_for_) release();
        kept_for_ = generation;
    }

private:
    Factory make_;
    std::unique_ptr<Passes> passes_;
    Device device_ = Device::Cpu;
    uint64_t kept_for_ = 0;
};

}  // namespace voxlux
