// The Extinction-SAT passes as GL compute programs: sat_scan.comp scans the quantised light grid
// in place along x, y and z (96-bit running sums), light_cache.comp fills one light-cache channel
// per dispatch. The SAT and the mask of needed cells stay on the GPU across the channels of one SAT.
#include <epoxy/gl.h>

#include <stdexcept>
#include <string>

#include "gl/gl_buffer.h"
#include "gl/gl_context.h"
#include "lighting/extinction_sat/sat_passes.h"

namespace voxlux {
namespace {

class GlSatPasses final : public SatPasses {
public:
    void buildSat(const LightGrid& grid, SummedVolume& sat) override {
        quantizeLightGrid(grid, sat);
        ensureGlContext();
        const GLuint program = kernelProgram("sat_scan.comp");
        kernel::VxSatParams params{};
        params.dims = sat.dims;
        params.planes = sat.planes;
        sat_params_.upload(&params, sizeof params, GL_STREAM_DRAW, "SatParams");
        sat_params_.bind(program, GL_UNIFORM_BLOCK, "SatParams");
        const size_t bytes = sat.words.size() * sizeof(uint32_t);
        checkStorageSize("SatScan", bytes);
        sat_.upload(sat.words.data(), bytes, GL_DYNAMIC_COPY, "SatScan");
        sat_.bind(program, GL_SHADER_STORAGE_BLOCK, "SatScan");
        sat_generation_ = 0;  // the buffer now holds this scan, not a light pass's SAT
        glUseProgram(program);
        const GLint axis = glGetUniformLocation(program, "vx_scan_axis");
        const size_t entries = sat.planeEntries();
        const size_t length[3] = {size_t(sat.dims.x) + 1, size_t(sat.dims.y) + 1, size_t(sat.dims.z) + 1};
        for (int a = 0; a < 3; ++a) {
            glProgramUniform1i(program, axis, a);
            dispatchLinear(program, "vx_line_offset", entries / length[a] * size_t(sat.planes));
        }
        glGetNamedBufferSubData(sat_.id(), 0, GLsizeiptr(bytes), sat.words.data());
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: the SAT scan failed with GL error " + std::to_string(error));
    }

    void fillLightChannel(const LightPass& pass, LightCache& cache) override {
        ensureGlContext();
        const GLuint program = kernelProgram("light_cache.comp");
        sat_params_.upload(&pass.params, sizeof pass.params, GL_STREAM_DRAW, "SatParams");
        sat_params_.bind(program, GL_UNIFORM_BLOCK, "SatParams");
        // The SAT and the mask stay on the GPU across the passes of one SAT.
        if (pass.sat_generation != sat_generation_) {
            const size_t bytes = pass.sat->words.size() * sizeof(uint32_t);
            checkStorageSize("Sat", bytes);
            sat_.upload(pass.sat->words.data(), bytes, GL_STATIC_DRAW, "Sat");
            std::vector<uint8_t> needed(*pass.needed);
            needed.resize((needed.size() + 3) / 4 * 4, 0);  // whole uints
            needed_.upload(needed.data(), needed.size(), GL_STATIC_DRAW, "Needed");
            sat_generation_ = pass.sat_generation;
        }
        sat_.bind(program, GL_SHADER_STORAGE_BLOCK, "Sat");
        needed_.bind(program, GL_SHADER_STORAGE_BLOCK, "Needed");
        lights_.upload(pass.lights->data(), pass.lights->size() * sizeof(kernel::VxLight), GL_STREAM_DRAW, "Lights");
        lights_.bind(program, GL_SHADER_STORAGE_BLOCK, "Lights");
        const size_t cells = pass.needed->size();
        channel_.upload(nullptr, cells * sizeof(float), GL_STREAM_READ, "Channel");
        channel_.bind(program, GL_SHADER_STORAGE_BLOCK, "Channel");
        glUseProgram(program);
        dispatchLinear(program, "vx_cell_offset", cells);
        std::vector<float> values(cells);
        glGetNamedBufferSubData(channel_.id(), 0, GLsizeiptr(cells * sizeof(float)), values.data());
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: a light pass failed with GL error " + std::to_string(error));
        const int channel = pass.params.channel;
        for (size_t i = 0; i < cells; ++i)
            if ((*pass.needed)[i]) cache.values[i * size_t(cache.channels) + size_t(channel)] = values[i];
    }

private:
    GlBuffer sat_params_, sat_, needed_, lights_, channel_;
    uint64_t sat_generation_ = 0;   // LightPass::sat_generation of the SAT in sat_, 0 = none
};

}  // namespace

std::unique_ptr<SatPasses> makeGlSatPasses() {
    ensureGlContext();
    return std::make_unique<GlSatPasses>();
}

}  // namespace voxlux
