#include "kernel/shader_source.h"

#include <sstream>
#include <stdexcept>

namespace voxlux {
namespace {

const char* const kHeader = "#version 450 core\n#define VX_GLSL 1\n";

// Appends `text` without its C++-only #include / #pragma once lines.
void appendSource(std::string& out, const std::string& text) {
    std::istringstream in(text);
    std::string line;
    out += "#line 1\n";  // keeps compiler messages' line numbers per file
    while (std::getline(in, line)) {
        if (line.rfind("#include", 0) == 0 || line.rfind("#pragma once", 0) == 0) line.clear();
        out += line + "\n";
    }
}

void appendFile(std::string& out, const std::string& name) {
    const auto& files = embeddedShaders();
    auto it = files.find(name);
    if (it == files.end()) throw std::runtime_error("shader file " + name + " is not embedded");
    appendSource(out, it->second);
}

}  // namespace

std::string assembleComputeShader(const std::string& entry, const std::string& defines) {
    std::string out = kHeader + defines;
    for (const std::string& f : kernelProgramFiles()) appendFile(out, f);
    appendFile(out, entry);
    return out;
}

std::string assembleGradeShader(const std::string& ocio_shader) {
    std::string out = kHeader;
    appendFile(out, "vx_prelude.h");
    appendFile(out, "vx_kernel_bindings.h");
    appendFile(out, "vx_grade.h");
    appendSource(out, ocio_shader);
    appendFile(out, "grade.comp");
    return out;
}

}  // namespace voxlux
