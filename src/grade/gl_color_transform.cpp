#include "grade/gl_color_transform.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "gl/gl_context.h"
#include "gl/gl_program.h"
#include "kernel/kernel_types.h"
#include "kernel/shader_source.h"

namespace voxlux {
namespace {
namespace OCIO = OCIO_NAMESPACE;

// Pixels per dispatch: 16 MiB, within the 128 MiB shader storage block every GL 4.5 allows, and
// 16384 groups of 64 (local_size_x in grade.comp), within the 65535-group limit.
constexpr size_t kBlockPixels = size_t(1) << 20;
constexpr size_t kGroupSize = 64;

// A frame applies up to three processors (beauty, AOVs, preview); a grade animated per frame makes
// a new one every frame, whose programs and LUTs must not pile up on the GPU.
constexpr size_t kCachedPrograms = 8;

OCIO::GpuShaderDescRcPtr describe(const OCIO::ConstProcessorRcPtr& processor) {
    OCIO::GpuShaderDescRcPtr desc = OCIO::GpuShaderDesc::CreateShaderDesc();
    desc->setLanguage(OCIO::GPU_LANGUAGE_GLSL_4_0);
    desc->setFunctionName("ocio_transform");  // what grade.comp calls
    desc->setResourcePrefix("ocio_");         // apart from the vx_ names
    processor->getOptimizedGPUProcessor(OCIO::OPTIMIZATION_DEFAULT)->extractGpuShaderInfo(desc);
    return desc;
}

// A LUT texture as the desc asks for it: 32-bit float, clamped at the edges, filtered as asked,
// except that the shader's tetrahedral code reads texel centres and interpolates itself, which
// nearest filtering keeps exact.
GLuint makeLut(GLenum target, GLenum format, GLenum channels, glm::uvec3 size, OCIO::Interpolation interpolation,
               const float* values) {
    GLuint texture = 0;
    glCreateTextures(target, 1, &texture);
    const auto x = GLsizei(size.x), y = GLsizei(size.y), z = GLsizei(size.z);
    switch (target) {
        case GL_TEXTURE_1D:
            glTextureStorage1D(texture, 1, format, x);
            glTextureSubImage1D(texture, 0, 0, x, channels, GL_FLOAT, values);
            break;
        case GL_TEXTURE_2D:
            glTextureStorage2D(texture, 1, format, x, y);
            glTextureSubImage2D(texture, 0, 0, 0, x, y, channels, GL_FLOAT, values);
            break;
        default:
            glTextureStorage3D(texture, 1, format, x, y, z);
            glTextureSubImage3D(texture, 0, 0, 0, 0, x, y, z, channels, GL_FLOAT, values);
    }
    const GLint filter =
        interpolation == OCIO::INTERP_NEAREST || interpolation == OCIO::INTERP_TETRAHEDRAL ? GL_NEAREST : GL_LINEAR;
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, filter);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTextureParameteri(texture, wrap, GL_CLAMP_TO_EDGE);
    return texture;
}

// Dynamic properties (exposure, grading primaries, curves) are uniforms. Their values are not
// part of the processor's cache ID, so each call sets them from its own processor's desc.
void setUniforms(GLuint program, const OCIO::GpuShaderDesc& desc) {
    for (unsigned i = 0; i < desc.getNumUniforms(); ++i) {
        OCIO::GpuShaderDesc::UniformData data;
        const char* name = desc.getUniform(i, data);
        const GLint at = glGetUniformLocation(program, name);
        switch (data.m_type) {
            case OCIO::UNIFORM_DOUBLE:
                glProgramUniform1f(program, at, float(data.m_getDouble()));
                break;
            case OCIO::UNIFORM_BOOL:
                glProgramUniform1i(program, at, data.m_getBool() ? 1 : 0);
                break;
            case OCIO::UNIFORM_FLOAT3: {
                const OCIO::Float3& v = data.m_getFloat3();
                glProgramUniform3f(program, at, v[0], v[1], v[2]);
                break;
            }
            case OCIO::UNIFORM_VECTOR_FLOAT:
                glProgramUniform1fv(program, at, data.m_vectorFloat.m_getSize(), data.m_vectorFloat.m_getVector());
                break;
            case OCIO::UNIFORM_VECTOR_INT:
                glProgramUniform1iv(program, at, data.m_vectorInt.m_getSize(), data.m_vectorInt.m_getVector());
                break;
            case OCIO::UNIFORM_UNKNOWN:
                throw std::runtime_error(std::string("GL backend: the OCIO uniform ") + name + " has no known type");
        }
    }
}

}  // namespace

struct GlColorTransform::Program {
    std::string cache_id;
    GLuint id = 0;
    std::vector<GLuint> luts;  // on texture units 0, 1, ... in this order
    bool dynamic = false;      // has uniforms
    GLint pixel_count = -1, unpremultiply = -1;

    Program() = default;
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;
    ~Program() {
        glDeleteTextures(GLsizei(luts.size()), luts.data());
        glDeleteProgram(id);
    }

    void addLut(const char* sampler, GLuint texture) {
        glProgramUniform1i(id, glGetUniformLocation(id, sampler), GLint(luts.size()));
        luts.push_back(texture);
    }
};

GlColorTransform::GlColorTransform() { glCreateBuffers(1, &pixels_); }

GlColorTransform::~GlColorTransform() { glDeleteBuffers(1, &pixels_); }

GlColorTransform::Program& GlColorTransform::program(const OCIO::ConstProcessorRcPtr& processor) {
    const std::string cache_id = processor->getCacheID();
    auto hit = std::find_if(programs_.begin(), programs_.end(), [&](const auto& p) { return p->cache_id == cache_id; });
    if (hit != programs_.end()) {
        std::rotate(programs_.begin(), hit, hit + 1);
        return *programs_.front();
    }

    const OCIO::GpuShaderDescRcPtr desc = describe(processor);
    GLint units = 0;
    glGetIntegerv(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, &units);
    const unsigned luts = desc->getNum3DTextures() + desc->getNumTextures();
    if (luts > unsigned(units))
        throw std::runtime_error("GL backend: the colour transform samples " + std::to_string(luts) +
                                 " LUTs, above this GL's " + std::to_string(units) +
                                 " texture units per compute shader; use the CPU backend");
    auto p = std::make_unique<Program>();
    p->cache_id = cache_id;
    p->id = compileComputeProgram(assembleGradeShader(desc->getShaderText()),
                                  "grade.comp (OCIO processor " + cache_id + ")");
    p->pixel_count = glGetUniformLocation(p->id, "vx_pixel_count");
    p->unpremultiply = glGetUniformLocation(p->id, "vx_unpremultiply");
    p->dynamic = desc->getNumUniforms() > 0;
    for (unsigned i = 0; i < desc->getNum3DTextures(); ++i) {
        const char *texture = nullptr, *sampler = nullptr;
        unsigned edge = 0;
        OCIO::Interpolation interpolation = OCIO::INTERP_UNKNOWN;
        const float* values = nullptr;
        desc->get3DTexture(i, texture, sampler, edge, interpolation);
        desc->get3DTextureValues(i, values);
        p->addLut(sampler, makeLut(GL_TEXTURE_3D, GL_RGB32F, GL_RGB, glm::uvec3(edge), interpolation, values));
    }
    for (unsigned i = 0; i < desc->getNumTextures(); ++i) {
        const char *texture = nullptr, *sampler = nullptr;
        unsigned width = 0, height = 0;
        OCIO::GpuShaderDesc::TextureType channel = OCIO::GpuShaderDesc::TEXTURE_RGB_CHANNEL;
        OCIO::Interpolation interpolation = OCIO::INTERP_UNKNOWN;
        const float* values = nullptr;
        desc->getTexture(i, texture, sampler, width, height, channel, interpolation);
        desc->getTextureValues(i, values);
        // OCIO 2.1 declares a sampler1D when the height is 1, and folds longer 1D LUTs (over the
        // desc's 4096-texel width) into the rows of a sampler2D.
        const bool red = channel == OCIO::GpuShaderDesc::TEXTURE_RED_CHANNEL;
        p->addLut(sampler, makeLut(height == 1 ? GL_TEXTURE_1D : GL_TEXTURE_2D, red ? GL_R32F : GL_RGB32F,
                                   red ? GL_RED : GL_RGB, glm::uvec3(width, height, 1), interpolation, values));
    }
    programs_.insert(programs_.begin(), std::move(p));
    if (programs_.size() > kCachedPrograms) programs_.pop_back();
    return *programs_.front();
}

void GlColorTransform::transformColors(const OCIO::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                                       bool unpremultiply) {
    ensureGlContext();   // current on this thread
    if (processor->isNoOp() || rgba.empty()) return;
    const Program& p = program(processor);
    if (p.dynamic) setUniforms(p.id, *describe(processor));
    glProgramUniform1i(p.id, p.unpremultiply, unpremultiply ? 1 : 0);
    glUseProgram(p.id);
    for (size_t unit = 0; unit < p.luts.size(); ++unit) glBindTextureUnit(GLuint(unit), p.luts[unit]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, VX_BIND_PIXELS, pixels_);
    const size_t block = std::min(rgba.size(), kBlockPixels);
    glNamedBufferData(pixels_, GLsizeiptr(block * sizeof(glm::vec4)), nullptr, GL_STREAM_COPY);
    for (size_t first = 0; first < rgba.size(); first += block) {
        const size_t n = std::min(block, rgba.size() - first);
        const auto bytes = GLsizeiptr(n * sizeof(glm::vec4));
        glNamedBufferSubData(pixels_, 0, bytes, &rgba[first]);
        glProgramUniform1i(p.id, p.pixel_count, GLint(n));
        glDispatchCompute(GLuint((n + kGroupSize - 1) / kGroupSize), 1, 1);
        // Reading back waits for the dispatch, so the next block's upload cannot overtake it.
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(pixels_, 0, bytes, &rgba[first]);
    }
    if (GLenum error = glGetError(); error != GL_NO_ERROR)
        throw std::runtime_error("GL backend: the colour transform failed with GL error " + std::to_string(error));
}

std::unique_ptr<ColorTransformer> makeGlColorTransformer() {
    ensureGlContext();
    return std::make_unique<GlColorTransform>();
}

}  // namespace voxlux
