// Propagation sweeps as the GL compute program propagate.comp: one dispatch per slice, two slice
// buffers swapped between slices, each light's sweep adding into its light group's volume block on
// the GPU.
#include <epoxy/gl.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "lighting/propagation/kernel/cpu_propagation_kernel.h"
#include "gl/gl_buffer.h"
#include "gl/gl_context.h"
#include "lighting/propagation/propagation_passes.h"

namespace voxlux {
namespace {

class GlPropagationPasses final : public PropagationPasses {
public:
    // The pass's lights run one after another over buffers uploaded once: each light's sweep is a
    // dispatch per slice with its own two slice buffers, adding into the volume block on the GPU.
    void propagate(const PropagationPass& pass, IlluminationVolume& volume) override {
        ensureGlContext();
        const GLuint program = kernelProgram("propagate.comp");
        const kernel::VxPropParams& first = pass.sweeps.front();
        kernel::CpuPropagationKernel axes;
        const int axis = first.axis, u = axes.vx_axis_u(axis), v = axes.vx_axis_v(axis);
        const size_t slice_cells = size_t(first.dims[u]) * first.dims[v];
        // The pass's RGB blocks: from its offset to the end of the last light group's block its
        // sweeps add into (VxPropParams::block_first).
        int last_first = 0;
        for (const kernel::VxPropParams& Q : pass.sweeps) last_first = std::max(last_first, Q.block_first);
        const size_t block = size_t(last_first) + size_t(first.dims.x) * first.dims.y * first.dims.z * 3;
        march_params_.upload(pass.march, sizeof *pass.march, GL_STREAM_DRAW, "Params");
        march_params_.bind(program, GL_UNIFORM_BLOCK, "Params");
        const struct {
            GlBuffer& buffer;
            const char* name;
            const void* data;
            size_t bytes;
        } arrays[] = {
            {prop_sigma_, "PropSigma", pass.sigma->data(), pass.sigma->size() * sizeof(float)},
            {noise_, "Noise", pass.noise->data(), pass.noise->size() * sizeof(glm::vec4)},
            {prop_in_, "SweepInput", pass.input ? pass.input->data() : nullptr, pass.input ? pass.input->size() * sizeof(float) : 0},
            {volume_, "Volume", volume.values.data() + pass.offset, block * sizeof(float)},
        };
        for (const auto& a : arrays) {
            checkStorageSize(a.name, a.bytes);
            a.buffer.upload(a.data, a.bytes, GL_DYNAMIC_COPY, a.name);
            a.buffer.bind(program, GL_SHADER_STORAGE_BLOCK, a.name);
        }
        glUseProgram(program);
        // Two slice buffers, swapped between slices: one read (SliceIn), one written (SliceOut).
        GlBuffer* slices[2] = {&slice_a_, &slice_b_};
        for (const kernel::VxPropParams& Q : pass.sweeps) {
            for (GlBuffer* b : slices) b->upload(nullptr, slice_cells * Q.channels * sizeof(float), GL_DYNAMIC_COPY, "slice");
            kernel::VxPropParams params = Q;
            params.strides = glm::ivec3(1, Q.dims.x, Q.dims.x * Q.dims.y);   // the volume's own layout
            const int count = Q.dims[axis];
            for (int step = 0; step < count; ++step) {
                params.slice = Q.direction > 0 ? step : count - 1 - step;
                prop_params_.upload(&params, sizeof params, GL_STREAM_DRAW, "PropParams");
                prop_params_.bind(program, GL_UNIFORM_BLOCK, "PropParams");
                slices[step & 1]->bind(program, GL_SHADER_STORAGE_BLOCK, "SliceIn");
                slices[(step + 1) & 1]->bind(program, GL_SHADER_STORAGE_BLOCK, "SliceOut");
                glDispatchCompute(GLuint((slice_cells + kLinearGroup - 1) / kLinearGroup), 1, 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT);
            }
        }
        glGetNamedBufferSubData(volume_.id(), 0, GLsizeiptr(block * sizeof(float)), volume.values.data() + pass.offset);
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: a propagation pass failed with GL error " + std::to_string(error));
    }

private:
    GlBuffer march_params_, prop_params_, prop_sigma_, noise_, prop_in_, volume_, slice_a_, slice_b_;
};

}  // namespace

std::unique_ptr<PropagationPasses> makeGlPropagationPasses() {
    ensureGlContext();
    return std::make_unique<GlPropagationPasses>();
}

}  // namespace voxlux
