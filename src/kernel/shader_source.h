// GLSL source of the GL compute shaders, assembled from the embedded shaders/ files.
#pragma once
#include <map>
#include <string>

namespace voxlux {

const std::map<std::string, std::string>& embeddedShaders();  // generated at build time

// "#version 450" + "#define VX_GLSL" + the shared kernel headers in dependency order (with the GL
// data bindings, vx_gl_bindings.glsl, right after vx_types.h) + `entry` (e.g. "march.comp"), with
// the C++-only #include / #pragma once lines removed. `defines` goes right after the header.
std::string assembleComputeShader(const std::string& entry, const std::string& defines = "");

// The grade stage's program: the same header + vx_prelude.h + vx_grade.h + `ocio_shader` (an OCIO
// processor's generated GLSL, declaring ocio_transform) + grade.comp.
std::string assembleGradeShader(const std::string& ocio_shader);

}  // namespace voxlux
