// The GL side of the kernel contract (cmake/kernel_contract.cmake): every kernel program, the
// march's and each lighting method's, compiles from the generated program order, and within one
// program no two active blocks share a binding point, each block sitting at its generated
// VX_BIND_* number.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "gl/gl_buffer.h"
#include "gl/gl_context.h"
#include "kernel/kernel_types.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

struct ActiveBlock {
    std::string name;
    GLint binding;
};

std::vector<ActiveBlock> activeBlocks(GLuint program, GLenum interface) {
    GLint count = 0;
    glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
    std::vector<ActiveBlock> blocks;
    for (GLint i = 0; i < count; ++i) {
        char name[128];
        glGetProgramResourceName(program, interface, GLuint(i), sizeof name, nullptr, name);
        const GLenum property = GL_BUFFER_BINDING;
        GLint binding = -1;
        glGetProgramResourceiv(program, interface, GLuint(i), 1, &property, 1, nullptr, &binding);
        blocks.push_back({name, binding});
    }
    return blocks;
}

TEST(KernelPrograms, EveryProgramKeepsItsBlocksApartAtTheirGeneratedBindings) {
    VOXLUX_REQUIRE_GL(gl);
    ensureGlContext();
    // The blocks each program must read, at the numbers the contract generated for them.
    const std::map<std::string, GLint> storage = {
        {"AtlasDensity", VX_BIND_ATLAS_DENSITY}, {"PageTable", VX_BIND_PAGE_TABLE}, {"Lights", VX_BIND_LIGHTS},
        {"LightCache", VX_BIND_LIGHT_CACHE},     {"Illumination", VX_BIND_ILLUMINATION}, {"Band", VX_BIND_BAND},
        {"Sat", VX_BIND_SAT},                    {"Channel", VX_BIND_CHANNEL},           {"SatScan", VX_BIND_SAT_SCAN},
        {"PropSigma", VX_BIND_PROP_SIGMA},       {"Volume", VX_BIND_VOLUME},             {"SliceOut", VX_BIND_SLICE_OUT}};
    const std::map<std::string, GLint> uniform = {
        {"Params", VX_BIND_PARAMS}, {"Lighting", VX_BIND_LIGHTING}, {"SatParams", VX_BIND_SAT_PARAMS}, {"PropParams", VX_BIND_PROP_PARAMS}};
    const std::map<std::string, std::vector<std::string>> wanted = {
        {"march.comp", {"AtlasDensity", "PageTable", "Lights", "LightCache", "Illumination", "Band", "Params", "Lighting"}},
        {"light_cache.comp", {"Sat", "Channel", "SatParams"}},
        {"sat_scan.comp", {"SatScan", "SatParams"}},
        {"propagate.comp", {"PropSigma", "Volume", "SliceOut", "PropParams"}}};
    for (const auto& [entry, names] : wanted) {
        const GLuint program = kernelProgram(entry);
        std::set<std::string> seen;
        for (const auto& [interface, numbers] : {std::pair{GL_SHADER_STORAGE_BLOCK, &storage}, std::pair{GL_UNIFORM_BLOCK, &uniform}}) {
            std::set<GLint> bindings;
            for (const ActiveBlock& b : activeBlocks(program, interface)) {
                seen.insert(b.name);
                EXPECT_TRUE(bindings.insert(b.binding).second) << entry << ": " << b.name << " shares binding " << b.binding;
                if (const auto n = numbers->find(b.name); n != numbers->end()) {
                    EXPECT_EQ(b.binding, n->second) << entry << ": " << b.name;
                }
            }
        }
        for (const std::string& name : names) EXPECT_TRUE(seen.count(name)) << entry << " does not read " << name;
    }
}

}  // namespace
}  // namespace voxlux::test
