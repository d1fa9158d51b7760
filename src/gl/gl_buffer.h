// What every GL pass shares: storage and uniform buffers bound by block name, the kernel's
// compute programs (one per entry point and process), and dispatches of one-dimensional passes
// within GL's group limits. The march (gl_backend.cpp) and each lighting method's GL passes use
// them on the process's EGL context (gl_context.h).
#pragma once
#include <epoxy/gl.h>

#include <cstddef>
#include <initializer_list>
#include <string>

namespace voxlux {

class GlBuffer {
public:
    GlBuffer();
    ~GlBuffer();
    GlBuffer(const GlBuffer&) = delete;
    GlBuffer& operator=(const GlBuffer&) = delete;

    // Replaces the contents. An empty array becomes 16 zero bytes: GL has no zero-size buffers and
    // the kernel never reads an array whose feature is off. Throws naming `what` when GL cannot
    // allocate it.
    void upload(const void* data, size_t bytes, GLenum usage, const std::string& what);
    // The same with several arrays one after the other (kernel arrays sharing one storage block).
    struct Part {
        const void* data;
        size_t bytes;
    };
    void upload(std::initializer_list<Part> parts, GLenum usage, const std::string& what);

    // Binds to the binding point the program declares for block `name`, if the program uses it.
    void bind(GLuint program, GLenum interface, const char* name) const;

    GLuint id() const { return id_; }

private:
    GLuint id_ = 0;
};

// The program of kernel entry point `entry` ("march.comp", ...) compiled with `defines` (lines of
// "#define NAME VALUE"), on first use.
GLuint kernelProgram(const std::string& entry, const std::string& defines = "");

// Throws when `bytes` is more than one shader storage block may address on this GL (atlases can
// outgrow it), naming `block` and pointing to the CPU backend.
void checkStorageSize(const char* block, size_t bytes);

// local_size_x of the one-dimensional passes (sat_scan.comp, light_cache.comp, propagate.comp).
constexpr int kLinearGroup = 64;

// Runs `count` invocations of `program` (already in use) in dispatches of at most 65535 groups,
// telling each its first invocation through the uniform `offset_uniform`.
void dispatchLinear(GLuint program, const char* offset_uniform, size_t count);

}  // namespace voxlux
