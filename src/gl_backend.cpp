// GL backend: the shared kernel as a compute shader (shaders/march.comp) on the process's headless
// EGL context. Inputs are uploaded as buffers each march; the image comes back in bands of rows.
#include <epoxy/gl.h>

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "gl_context.h"
#include "march_backend.h"
#include "shader_source.h"

namespace voxlux {
namespace {

// march.comp writes 13 floats per pixel in VxPixel's member order, so a band reads straight back.
static_assert(sizeof(kernel::VxPixel) == 13 * sizeof(float));
static_assert(offsetof(kernel::VxPixel, direct) == 4 * sizeof(float));
static_assert(offsetof(kernel::VxPixel, depth) == 11 * sizeof(float));

// Rows per dispatch: keeps each submission short whatever the image size (and the band buffer small).
constexpr int kBandRows = 64;
constexpr int kGroupSize = 8;  // local_size_x/y in march.comp

std::string describeBytes(size_t bytes) {
    return std::to_string(bytes) + " bytes (" + std::to_string(bytes >> 20) + " MiB)";
}

std::string infoLog(GLuint object, bool program) {
    GLint length = 0;
    (program ? glGetProgramiv : glGetShaderiv)(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    GLsizei written = 0;
    (program ? glGetProgramInfoLog : glGetShaderInfoLog)(object, GLsizei(log.size()), &written, log.data());
    log.resize(size_t(written));
    return log;
}

GLuint compileProgram(const std::string& entry) {
    const std::string source = assembleComputeShader(entry);
    const char* text = source.c_str();
    GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(shader, false);
        glDeleteShader(shader);
        throw std::runtime_error("GL compute shader " + entry + " does not compile:\n" + log);
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, shader);
    glLinkProgram(program);
    glDeleteShader(shader);  // only flagged: the program keeps it while attached
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(program, true);
        glDeleteProgram(program);
        throw std::runtime_error("GL compute shader " + entry + " does not link:\n" + log);
    }
    return program;
}

// One program per process, like the context it belongs to.
GLuint marchProgram() {
    static const GLuint program = compileProgram("march.comp");
    return program;
}

class Buffer {
public:
    Buffer() { glCreateBuffers(1, &id_); }
    ~Buffer() { glDeleteBuffers(1, &id_); }
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    // Replaces the contents. An empty array becomes 16 zero bytes: GL has no zero-size buffers and
    // the kernel never reads an array whose feature is off.
    void upload(const void* data, size_t bytes, GLenum usage, const std::string& what) {
        static const float kZeros[4] = {};
        if (bytes == 0) {
            data = kZeros;
            bytes = sizeof kZeros;
        }
        glNamedBufferData(id_, GLsizeiptr(bytes), data, usage);
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: cannot allocate the " + what + " buffer of " + describeBytes(bytes) +
                                     (error == GL_OUT_OF_MEMORY ? ": out of memory"
                                                                : ": GL error " + std::to_string(error)));
    }

    // Binds to the binding point the program declares for block `name`, if the program uses it.
    void bind(GLuint program, GLenum interface, const char* name) const {
        const GLuint index = glGetProgramResourceIndex(program, interface, name);
        if (index == GL_INVALID_INDEX) return;
        const GLenum property = GL_BUFFER_BINDING;
        GLint binding = 0;
        glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &binding);
        const GLenum target = interface == GL_UNIFORM_BLOCK ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER;
        glBindBufferBase(target, GLuint(binding), id_);
    }

    GLuint id() const { return id_; }

private:
    GLuint id_ = 0;
};

class GlBackend final : public MarchBackend {
public:
    GlBackend()
        : context_(ensureGlContext()),
          program_(marchProgram()),
          row_offset_(glGetUniformLocation(program_, "vx_row_offset")) {
        glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_storage_block_);
    }

    std::string name() const override { return "gl (" + context_.renderer + ")"; }

    RenderImage march(const KernelInputs& in) override {
        ensureGlContext();  // current on this thread
        RenderImage img;
        img.width = int(in.params.camera_frame.z);
        img.height = int(in.params.camera_frame.w);
        img.pixels.resize(size_t(img.width) * img.height);
        if (img.pixels.empty()) return img;

        params_.upload(&in.params, sizeof in.params, GL_STREAM_DRAW, "parameter");
        params_.bind(program_, GL_UNIFORM_BLOCK, "Params");
        const BrickAtlas& atlas = *in.atlas;
        const struct {
            Buffer& buffer;
            const char* block;
            const void* data;
            size_t bytes;
        } arrays[] = {
            {density_, "AtlasDensity", atlas.density.data(), atlas.density.size() * sizeof(float)},
            {emission_, "AtlasEmission", atlas.emission.data(), atlas.emission.size() * sizeof(float)},
            {color_, "AtlasColor", atlas.color.data(), atlas.color.size() * sizeof(float)},
            {pages_, "PageTable", in.pages->entries.data(), in.pages->entries.size() * sizeof(glm::ivec4)},
            {lights_, "Lights", in.lights.data(), in.lights.size() * sizeof(kernel::VxLight)},
            {tf_lut_, "TransferLut", in.tf_lut.data(), in.tf_lut.size() * sizeof(glm::vec4)},
        };
        for (const auto& a : arrays) {
            checkStorageSize(a.block, a.bytes);
            a.buffer.upload(a.data, a.bytes, GL_STATIC_DRAW, a.block);
            a.buffer.bind(program_, GL_SHADER_STORAGE_BLOCK, a.block);
        }

        const size_t row_bytes = size_t(img.width) * sizeof(kernel::VxPixel);
        const int band_rows = std::min(kBandRows, img.height);
        checkStorageSize("Band", row_bytes * band_rows);
        band_.upload(nullptr, row_bytes * band_rows, GL_STREAM_READ, "Band");
        band_.bind(program_, GL_SHADER_STORAGE_BLOCK, "Band");

        glUseProgram(program_);
        for (int y0 = 0; y0 < img.height; y0 += band_rows) {
            const int rows = std::min(band_rows, img.height - y0);
            glProgramUniform1i(program_, row_offset_, y0);
            glDispatchCompute(GLuint((img.width + kGroupSize - 1) / kGroupSize),
                              GLuint((rows + kGroupSize - 1) / kGroupSize), 1);
            // Reading the band back waits for the dispatch, so only one band is ever in flight.
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            glGetNamedBufferSubData(band_.id(), 0, GLsizeiptr(row_bytes * rows),
                                    &img.pixels[size_t(y0) * img.width]);
        }
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: the march failed with GL error " + std::to_string(error));
        return img;
    }

private:
    // Atlases can outgrow what one shader storage block may address on this GL.
    void checkStorageSize(const char* block, size_t bytes) const {
        if (GLint64(bytes) > max_storage_block_)
            throw std::runtime_error(std::string("GL backend: the ") + block + " buffer needs " + describeBytes(bytes) +
                                     ", above this GL's shader storage block limit of " +
                                     describeBytes(size_t(max_storage_block_)) +
                                     " (GL_MAX_SHADER_STORAGE_BLOCK_SIZE); use the CPU backend");
    }

    const GlContextInfo& context_;
    const GLuint program_;
    const GLint row_offset_;
    GLint64 max_storage_block_ = 0;
    Buffer params_, density_, emission_, color_, pages_, lights_, tf_lut_, band_;
};

}  // namespace

std::unique_ptr<MarchBackend> makeGlBackend() { return std::make_unique<GlBackend>(); }

bool hardwareGlAvailable() {
    try {
        return !ensureGlContext().software;
    } catch (const std::runtime_error&) {
        return false;
    }
}

}  // namespace voxlux
