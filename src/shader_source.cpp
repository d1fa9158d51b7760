#include "shader_source.h"

#include <sstream>
#include <stdexcept>

namespace voxlux {

std::string assembleComputeShader(const std::string& entry) {
    // The GL bindings declare `P` and the data accessors, which the later headers call.
    static const char* kKernel[] = {"vx_prelude.h", "vx_types.h", "vx_gl_bindings.glsl", "vx_sample.h",
                                    "vx_optics.h", "vx_cache.h", "vx_illumination.h", "vx_noise.h",
                                    "vx_march.h", "vx_sat.h", "vx_propagation.h"};
    const auto& files = embeddedShaders();
    std::string out = "#version 450 core\n#define VX_GLSL 1\n";
    auto append = [&](const std::string& name) {
        auto it = files.find(name);
        if (it == files.end()) throw std::runtime_error("shader file " + name + " is not embedded");
        std::istringstream in(it->second);
        std::string line;
        int number = 0;
        out += "#line 1\n";  // keeps compiler messages' line numbers per file
        while (std::getline(in, line)) {
            ++number;
            if (line.rfind("#include", 0) == 0 || line.rfind("#pragma once", 0) == 0) line.clear();
            out += line + "\n";
        }
    };
    for (const char* f : kKernel) append(f);
    append(entry);
    return out;
}

}  // namespace voxlux
