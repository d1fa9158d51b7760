// GLSL source of the GL compute shaders, assembled from the embedded shaders/ files.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace voxlux {

const std::map<std::string, std::string>& embeddedShaders();  // generated at build time
// The kernel text's files in program order (generated from the kernel contract,
// cmake/kernel_contract.cmake): prelude and types, the lighting methods' types, the GL data, the
// core text, the methods' march hooks, the march, the methods' passes.
const std::vector<std::string>& kernelProgramFiles();

// "#version 450" + "#define VX_GLSL" + kernelProgramFiles() + `entry` (e.g. "march.comp"), with
// the C++-only #include / #pragma once lines removed. `defines` goes right after the header.
std::string assembleComputeShader(const std::string& entry, const std::string& defines = "");

// The grade stage's program: the same header + vx_prelude.h + vx_kernel_bindings.h + vx_grade.h + `ocio_shader` (an OCIO
// processor's generated GLSL, declaring ocio_transform) + grade.comp.
std::string assembleGradeShader(const std::string& ocio_shader);

}  // namespace voxlux
