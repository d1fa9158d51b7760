// The grade stage's colour transforms on one device: an OCIO processor applied in place to
// premultiplied RGBA. cpu: OCIO's CPU processor (cpu_color_transform.cpp); gl: the processor's
// generated GLSL and LUT textures (gl_color_transform.cpp).
#pragma once
#include <memory>
#include <vector>

#include <OpenColorIO/OpenColorIO.h>
#include <glm/glm.hpp>

#include "kernel/kernel_backend.h"

namespace voxlux {

class ColorTransformer {
public:
    virtual ~ColorTransformer() = default;
    // With `unpremultiply`, colour is divided by alpha where alpha > 0 and multiplied back after
    // (shaders/vx_grade.h); alpha is never changed. A no-op processor leaves `rgba` untouched.
    virtual void transformColors(const OCIO_NAMESPACE::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                                 bool unpremultiply) = 0;
};

std::unique_ptr<ColorTransformer> makeColorTransformer(Device device);

}  // namespace voxlux
