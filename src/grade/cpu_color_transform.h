// Grade stage on the CPU backend: an OCIO processor over premultiplied RGBA with OCIO's CPU
// processor (32-bit float in and out), between the premultiplication rules of shaders/vx_grade.h.
#pragma once
#include <vector>

#include <OpenColorIO/OpenColorIO.h>
#include <glm/glm.hpp>

namespace voxlux {

// ColorTransformer::transformColors on the CPU. A no-op processor leaves `rgba` untouched.
void transformColorsCpu(const OCIO_NAMESPACE::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                        bool unpremultiply);

}  // namespace voxlux
