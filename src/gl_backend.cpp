// GL backend: the shared kernel as compute shaders (march.comp, sat_scan.comp, light_cache.comp,
// propagate.comp) on the process's headless EGL context. Inputs are uploaded as buffers; the image
// comes back in bands of rows, the SAT, each light-cache channel and each swept volume block whole.
// The grade stage's colour transforms run in gl_color_transform.cpp.
#include <epoxy/gl.h>

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "cpu_kernel.h"
#include "gl_color_transform.h"
#include "gl_context.h"
#include "gl_program.h"
#include "kernel_backend.h"
#include "shader_source.h"
#include "summed_volume.h"

namespace voxlux {
namespace {

// march.comp writes 20 floats per pixel in VxPixel's member order, so a band reads straight back.
static_assert(sizeof(kernel::VxPixel) == 20 * sizeof(float));
static_assert(offsetof(kernel::VxPixel, direct) == 4 * sizeof(float));
static_assert(offsetof(kernel::VxPixel, ambient) == 7 * sizeof(float));
static_assert(offsetof(kernel::VxPixel, indirect) == 13 * sizeof(float));
static_assert(offsetof(kernel::VxPixel, depth) == 17 * sizeof(float));

// Rows per dispatch: keeps each submission short whatever the image size (and the band buffer small).
constexpr int kBandRows = 64;
constexpr int kGroupSize = 8;  // local_size_x/y in march.comp

std::string describeBytes(size_t bytes) {
    return std::to_string(bytes) + " bytes (" + std::to_string(bytes >> 20) + " MiB)";
}

GLuint compileProgram(const std::string& entry) { return compileComputeProgram(assembleComputeShader(entry), entry); }

// One program per entry point and process, like the context they belong to.
GLuint marchProgram() {
    static const GLuint program = compileProgram("march.comp");
    return program;
}
GLuint satScanProgram() {
    static const GLuint program = compileProgram("sat_scan.comp");
    return program;
}
GLuint lightCacheProgram() {
    static const GLuint program = compileProgram("light_cache.comp");
    return program;
}
GLuint propagateProgram() {
    static const GLuint program = compileProgram("propagate.comp");
    return program;
}

// Invocations per dispatch of the one-dimensional passes: whole groups within the 65535-group
// limit every GL 4.5 implementation has.
constexpr int kLinearGroup = 64;  // local_size_x of sat_scan.comp and light_cache.comp
constexpr int kMaxGroups = 65535;

// Runs `count` invocations of `program` (already in use) in dispatches of at most kMaxGroups
// groups, telling each its first invocation through the uniform `offset_uniform`.
void dispatchLinear(GLuint program, const char* offset_uniform, size_t count) {
    const GLint offset = glGetUniformLocation(program, offset_uniform);
    const size_t per_dispatch = size_t(kMaxGroups) * kLinearGroup;
    for (size_t first = 0; first < count; first += per_dispatch) {
        const size_t n = std::min(per_dispatch, count - first);
        glProgramUniform1i(program, offset, GLint(first));
        glDispatchCompute(GLuint((n + kLinearGroup - 1) / kLinearGroup), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
}

class Buffer {
public:
    Buffer() { glCreateBuffers(1, &id_); }
    ~Buffer() { glDeleteBuffers(1, &id_); }
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    // Replaces the contents. An empty array becomes 16 zero bytes: GL has no zero-size buffers and
    // the kernel never reads an array whose feature is off.
    void upload(const void* data, size_t bytes, GLenum usage, const std::string& what) {
        static const float kZeros[4] = {};
        if (bytes == 0) {
            data = kZeros;
            bytes = sizeof kZeros;
        }
        glNamedBufferData(id_, GLsizeiptr(bytes), data, usage);
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: cannot allocate the " + what + " buffer of " + describeBytes(bytes) +
                                     (error == GL_OUT_OF_MEMORY ? ": out of memory"
                                                                : ": GL error " + std::to_string(error)));
    }

    // Binds to the binding point the program declares for block `name`, if the program uses it.
    void bind(GLuint program, GLenum interface, const char* name) const {
        const GLuint index = glGetProgramResourceIndex(program, interface, name);
        if (index == GL_INVALID_INDEX) return;
        const GLenum property = GL_BUFFER_BINDING;
        GLint binding = 0;
        glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &binding);
        const GLenum target = interface == GL_UNIFORM_BLOCK ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER;
        glBindBufferBase(target, GLuint(binding), id_);
    }

    GLuint id() const { return id_; }

private:
    GLuint id_ = 0;
};

class GlBackend final : public KernelBackend {
public:
    GlBackend()
        : context_(ensureGlContext()),
          program_(marchProgram()),
          row_offset_(glGetUniformLocation(program_, "vx_row_offset")) {
        glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_storage_block_);
    }

    std::string name() const override { return "gl (" + context_.renderer + ")"; }

    RenderImage march(const KernelInputs& in) override {
        ensureGlContext();  // current on this thread
        RenderImage img;
        img.width = in.params.width;
        img.height = in.params.height;
        img.pixels.resize(size_t(img.width) * img.height);
        if (img.pixels.empty()) return img;

        params_.upload(&in.params, sizeof in.params, GL_STREAM_DRAW, "parameter");
        params_.bind(program_, GL_UNIFORM_BLOCK, "Params");
        const BrickAtlas& atlas = *in.atlas;
        const struct {
            Buffer& buffer;
            const char* block;
            const void* data;
            size_t bytes;
        } arrays[] = {
            {density_, "AtlasDensity", atlas.density.data(), atlas.density.size() * sizeof(float)},
            {emission_, "AtlasEmission", atlas.emission.data(), atlas.emission.size() * sizeof(float)},
            {color_, "AtlasColor", atlas.color.data(), atlas.color.size() * sizeof(float)},
            {pages_, "PageTable", in.pages->entries.data(), in.pages->entries.size() * sizeof(glm::ivec4)},
            {lights_, "Lights", in.lights.data(), in.lights.size() * sizeof(kernel::VxLight)},
            {tf_lut_, "TransferLut", in.tf_lut.data(), in.tf_lut.size() * sizeof(glm::vec4)},
            {emission_lut_, "EmissionLut", in.emission_lut.data(), in.emission_lut.size() * sizeof(glm::vec4)},
            {cache_, "LightCache", in.light_cache ? in.light_cache->values.data() : nullptr,
             in.light_cache ? in.light_cache->values.size() * sizeof(float) : 0},
            {illum_, "Illumination", in.illumination ? in.illumination->values.data() : nullptr,
             in.illumination ? in.illumination->values.size() * sizeof(float) : 0},
            {noise_, "Noise", in.noise.data(), in.noise.size() * sizeof(glm::vec4)},
        };
        for (const auto& a : arrays) {
            checkStorageSize(a.block, a.bytes);
            a.buffer.upload(a.data, a.bytes, GL_STATIC_DRAW, a.block);
            a.buffer.bind(program_, GL_SHADER_STORAGE_BLOCK, a.block);
        }

        const size_t row_bytes = size_t(img.width) * sizeof(kernel::VxPixel);
        const int band_rows = std::min(kBandRows, img.height);
        checkStorageSize("Band", row_bytes * band_rows);
        band_.upload(nullptr, row_bytes * band_rows, GL_STREAM_READ, "Band");
        band_.bind(program_, GL_SHADER_STORAGE_BLOCK, "Band");

        glUseProgram(program_);
        for (int y0 = 0; y0 < img.height; y0 += band_rows) {
            const int rows = std::min(band_rows, img.height - y0);
            glProgramUniform1i(program_, row_offset_, y0);
            glDispatchCompute(GLuint((img.width + kGroupSize - 1) / kGroupSize),
                              GLuint((rows + kGroupSize - 1) / kGroupSize), 1);
            // Reading the band back waits for the dispatch, so only one band is ever in flight.
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            glGetNamedBufferSubData(band_.id(), 0, GLsizeiptr(row_bytes * rows),
                                    &img.pixels[size_t(y0) * img.width]);
        }
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: the march failed with GL error " + std::to_string(error));
        return img;
    }

    void buildSat(const LightGrid& grid, SummedVolume& sat) override {
        quantizeLightGrid(grid, sat);
        ensureGlContext();
        const GLuint program = satScanProgram();
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
        const GLuint program = lightCacheProgram();
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

    // The pass's lights run one after another over buffers uploaded once: each light's sweep is a
    // dispatch per slice with its own two slice buffers, adding into the volume block on the GPU.
    void propagate(const PropagationPass& pass, IlluminationVolume& volume) override {
        ensureGlContext();
        const GLuint program = propagateProgram();
        const kernel::VxPropParams& first = pass.sweeps.front();
        kernel::CpuKernel axes;
        const int axis = first.axis, u = axes.vx_axis_u(axis), v = axes.vx_axis_v(axis);
        const size_t slice_cells = size_t(first.dims[u]) * first.dims[v];
        const size_t block = size_t(first.dims.x) * first.dims.y * first.dims.z * 3;
        march_params_.upload(pass.march, sizeof *pass.march, GL_STREAM_DRAW, "Params");
        march_params_.bind(program, GL_UNIFORM_BLOCK, "Params");
        const struct {
            Buffer& buffer;
            const char* name;
            const void* data;
            size_t bytes;
        } arrays[] = {
            {prop_sigma_, "PropSigma", pass.sigma->data(), pass.sigma->size() * sizeof(float)},
            {noise_, "Noise", pass.noise->data(), pass.noise->size() * sizeof(glm::vec4)},
            {prop_in_, "EyeInput", pass.input ? pass.input->data() : nullptr, pass.input ? pass.input->size() * sizeof(float) : 0},
            {volume_, "Volume", volume.values.data() + pass.offset, block * sizeof(float)},
        };
        for (const auto& a : arrays) {
            checkStorageSize(a.name, a.bytes);
            a.buffer.upload(a.data, a.bytes, GL_DYNAMIC_COPY, a.name);
            a.buffer.bind(program, GL_SHADER_STORAGE_BLOCK, a.name);
        }
        glUseProgram(program);
        // Two slice buffers, swapped between slices: one read (SliceIn), one written (SliceOut).
        Buffer* slices[2] = {&slice_a_, &slice_b_};
        for (const kernel::VxPropParams& Q : pass.sweeps) {
            for (Buffer* b : slices) b->upload(nullptr, slice_cells * Q.channels * sizeof(float), GL_DYNAMIC_COPY, "slice");
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

    void transformColors(const OCIO_NAMESPACE::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                         bool unpremultiply) override {
        ensureGlContext();
        grade_.apply(processor, rgba, unpremultiply);
    }

private:
    // Atlases can outgrow what one shader storage block may address on this GL.
    void checkStorageSize(const char* block, size_t bytes) const {
        if (GLint64(bytes) > max_storage_block_)
            throw std::runtime_error(std::string("GL backend: the ") + block + " buffer needs " + describeBytes(bytes) +
                                     ", above this GL's shader storage block limit of " +
                                     describeBytes(size_t(max_storage_block_)) +
                                     " (GL_MAX_SHADER_STORAGE_BLOCK_SIZE); use the CPU backend");
    }

    const GlContextInfo& context_;
    const GLuint program_;
    const GLint row_offset_;
    GLint64 max_storage_block_ = 0;
    Buffer params_, density_, emission_, color_, pages_, lights_, tf_lut_, emission_lut_, cache_, band_;
    Buffer sat_params_, sat_, needed_, channel_;
    Buffer illum_, noise_, march_params_, prop_params_, prop_sigma_, prop_in_, volume_, slice_a_, slice_b_;
    uint64_t sat_generation_ = 0;   // LightPass::sat_generation of the SAT in sat_, 0 = none
    GlColorTransform grade_;
};

}  // namespace

std::unique_ptr<KernelBackend> makeGlBackend() { return std::make_unique<GlBackend>(); }

bool hardwareGlAvailable() {
    try {
        return !ensureGlContext().software;
    } catch (const std::runtime_error&) {
        return false;
    }
}

}  // namespace voxlux
