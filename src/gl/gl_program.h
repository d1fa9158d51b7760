// Compiling GL compute shaders into programs on the current context.
#pragma once
#include <epoxy/gl.h>

#include <string>

namespace voxlux {

// Compiles and links `source`; throws std::runtime_error naming `what`, with the driver's log.
GLuint compileComputeProgram(const std::string& source, const std::string& what);

}  // namespace voxlux
