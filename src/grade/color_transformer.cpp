#include "grade/color_transformer.h"

#include "grade/cpu_color_transform.h"

namespace voxlux {

#if VOXLUX_HAS_GL
std::unique_ptr<ColorTransformer> makeGlColorTransformer();   // gl_color_transform.cpp
#endif

namespace {

class CpuColorTransformer final : public ColorTransformer {
public:
    void transformColors(const OCIO_NAMESPACE::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                         bool unpremultiply) override {
        transformColorsCpu(processor, rgba, unpremultiply);
    }
};

}  // namespace

std::unique_ptr<ColorTransformer> makeColorTransformer(Device device) {
#if VOXLUX_HAS_GL
    if (device == Device::Gl) return makeGlColorTransformer();
#endif
    (void)device;
    return std::make_unique<CpuColorTransformer>();
}

}  // namespace voxlux
