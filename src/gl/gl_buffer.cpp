#include "gl/gl_buffer.h"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "gl/gl_program.h"
#include "kernel/shader_source.h"

namespace voxlux {
namespace {

std::string describeBytes(size_t bytes) {
    return std::to_string(bytes) + " bytes (" + std::to_string(bytes >> 20) + " MiB)";
}

// Every GL 4.5 implementation allows this many groups per dispatch dimension.
constexpr int kMaxGroups = 65535;

}  // namespace

GlBuffer::GlBuffer() { glCreateBuffers(1, &id_); }

GlBuffer::~GlBuffer() { glDeleteBuffers(1, &id_); }

void GlBuffer::upload(const void* data, size_t bytes, GLenum usage, const std::string& what) {
    upload({{data, bytes}}, usage, what);
}

void GlBuffer::upload(std::initializer_list<Part> parts, GLenum usage, const std::string& what) {
    static const float kZeros[4] = {};
    size_t bytes = 0;
    for (const Part& p : parts) bytes += p.bytes;
    if (bytes == 0) {
        glNamedBufferData(id_, GLsizeiptr(sizeof kZeros), kZeros, usage);
    } else if (parts.size() == 1) {
        glNamedBufferData(id_, GLsizeiptr(bytes), parts.begin()->data, usage);
    } else {
        glNamedBufferData(id_, GLsizeiptr(bytes), nullptr, usage);
        size_t at = 0;
        for (const Part& p : parts) {
            if (p.bytes) glNamedBufferSubData(id_, GLsizeiptr(at), GLsizeiptr(p.bytes), p.data);
            at += p.bytes;
        }
    }
    if (GLenum error = glGetError(); error != GL_NO_ERROR)
        throw std::runtime_error("GL backend: cannot allocate the " + what + " buffer of " + describeBytes(bytes) +
                                 (error == GL_OUT_OF_MEMORY ? ": out of memory" : ": GL error " + std::to_string(error)));
}

void GlBuffer::bind(GLuint program, GLenum interface, const char* name) const {
    const GLuint index = glGetProgramResourceIndex(program, interface, name);
    if (index == GL_INVALID_INDEX) return;
    const GLenum property = GL_BUFFER_BINDING;
    GLint binding = 0;
    glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &binding);
    const GLenum target = interface == GL_UNIFORM_BLOCK ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER;
    glBindBufferBase(target, GLuint(binding), id_);
}

GLuint kernelProgram(const std::string& entry, const std::string& defines) {
    // One program per entry point, defines and process, like the context they belong to.
    static std::map<std::string, GLuint> programs;
    const std::string key = entry + "\n" + defines;
    auto it = programs.find(key);
    if (it == programs.end())
        it = programs.emplace(key, compileComputeProgram(assembleComputeShader(entry, defines), entry)).first;
    return it->second;
}

void checkStorageSize(const char* block, size_t bytes) {
    static const GLint64 limit = [] {
        GLint64 value = 0;
        glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &value);
        return value;
    }();
    if (GLint64(bytes) > limit)
        throw std::runtime_error(std::string("GL backend: the ") + block + " buffer needs " + describeBytes(bytes) +
                                 ", above this GL's shader storage block limit of " + describeBytes(size_t(limit)) +
                                 " (GL_MAX_SHADER_STORAGE_BLOCK_SIZE); use the CPU backend");
}

void dispatchLinear(GLuint program, const char* offset_uniform, size_t count) {
    const GLint offset = glGetUniformLocation(program, offset_uniform);
    const size_t per_dispatch = size_t(kMaxGroups) * kLinearGroup;
    for (size_t first = 0; first < count; first += per_dispatch) {
        const size_t n = std::min(per_dispatch, count - first);
        glProgramUniform1i(program, offset, GLint(first));
        glDispatchCompute(GLuint((n + kLinearGroup - 1) / kLinearGroup), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
}

}  // namespace voxlux
