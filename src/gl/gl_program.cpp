#include "gl/gl_program.h"

#include <algorithm>
#include <stdexcept>

namespace voxlux {
namespace {

std::string infoLog(GLuint object, bool program) {
    GLint length = 0;
    (program ? glGetProgramiv : glGetShaderiv)(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    GLsizei written = 0;
    (program ? glGetProgramInfoLog : glGetShaderInfoLog)(object, GLsizei(log.size()), &written, log.data());
    log.resize(size_t(written));
    return log;
}

}  // namespace

GLuint compileComputeProgram(const std::string& source, const std::string& what) {
    const char* text = source.c_str();
    GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(shader, false);
        glDeleteShader(shader);
        throw std::runtime_error("GL compute shader " + what + " does not compile:\n" + log);
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, shader);
    glLinkProgram(program);
    glDeleteShader(shader);  // only flagged: the program keeps it while attached
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(program, true);
        glDeleteProgram(program);
        throw std::runtime_error("GL compute shader " + what + " does not link:\n" + log);
    }
    return program;
}

}  // namespace voxlux
