// Grade stage on the GL backend: an OCIO processor as a compute shader. OCIO generates the
// processor's GLSL function (GPU_LANGUAGE_GLSL_4_0) and the LUTs it samples; shaders/grade.comp
// runs it over blocks of premultiplied RGBA between the premultiplication rules of vx_grade.h.
// Programs and LUT textures are kept per processor cache ID (the 8 last used), so a sequence
// compiles each processor once.
//
// Where it differs from the CPU processor (src/grade/cpu_color_transform.cpp): the GPU processor
// interpolates 1D LUTs and trilinear 3D LUTs with the texture units, whose filtering weights have
// as few as 8 fractional bits on hardware GPUs, so a linear LUT there may be off by up to about
// 1/512 of the step between neighbouring entries; tetrahedral 3D LUTs are interpolated in the
// shader from texel centres. Analytic steps use the GPU's own pow/exp2/log2.
// Measured on llvmpipe (tests/grade/test_color_transform.cpp, 65536 pixels a case): 3.7e-6 at most
// (the ACES 1.0 SDR video view), under 1e-6 for the CDLs and for every 1D and 3D LUT, linear or
// tetrahedral; exactly 0 for spi-anim's 131072-entry 1D LUT, as llvmpipe filters float textures
// with float weights. Unmeasured on a hardware GPU.
#pragma once
#include <epoxy/gl.h>

#include <memory>
#include <vector>

#include <OpenColorIO/OpenColorIO.h>
#include <glm/glm.hpp>

#include "grade/color_transformer.h"

namespace voxlux {

class GlColorTransform final : public ColorTransformer {
public:
    GlColorTransform();  // on the current context
    ~GlColorTransform();
    GlColorTransform(const GlColorTransform&) = delete;
    GlColorTransform& operator=(const GlColorTransform&) = delete;

    // On the current context. Throws std::runtime_error with the driver's log when the generated
    // shader does not compile, or on a GL error.
    void transformColors(const OCIO_NAMESPACE::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                         bool unpremultiply) override;

private:
    struct Program;
    Program& program(const OCIO_NAMESPACE::ConstProcessorRcPtr& processor);

    std::vector<std::unique_ptr<Program>> programs_;  // most recently used first
    GLuint pixels_ = 0;                               // the block of pixels grade.comp transforms
};

}  // namespace voxlux
