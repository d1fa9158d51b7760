// GL backend: the march (march.comp) on the process's headless EGL context. Inputs are uploaded as
// buffers; the image comes back in bands of rows. The lighting methods' GL passes
// (gl_sat_passes.cpp, gl_propagation_passes.cpp) and the grade stage's colour transforms
// (gl_color_transform.cpp) run on the same context.
#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "gl/gl_buffer.h"
#include "gl/gl_context.h"
#include "backend/backend_choice.h"
#include "kernel/cpu_kernel_data.h"

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
// The deep band's most bytes: 128 MiB, the shader storage block size every GL 4.3 driver supports.
constexpr size_t kDeepBandBytes = size_t(128) << 20;

class GlBackend final : public KernelBackend {
public:
    // Compiles the trilinear program up front, so a GL that cannot run the kernel fails here.
    GlBackend() : context_(ensureGlContext()) { marchProgram(VX_FILTER_TRILINEAR, 0, false); }

    std::string name() const override { return "gl (" + context_.renderer + ")"; }
    Device device() const override { return Device::Gl; }

    RenderImage march(const KernelInputs& in) override {
        ensureGlContext();  // current on this thread
        RenderImage img;
        img.width = in.params.width;
        img.height = in.params.height;
        img.pixels.resize(size_t(img.width) * img.height);
        if (img.pixels.empty()) return img;

        const int deep_samples = in.params.deep_samples;
        const GLuint program = marchProgram(in.params.voxel_filter, deep_samples, in.params.volume_count > 0);
        const GLint row_offset = glGetUniformLocation(program, "vx_row_offset");
        const GLint ray_uniform = glGetUniformLocation(program, "vx_ray");
        params_.upload(&in.params, sizeof in.params, GL_STREAM_DRAW, "parameter");
        params_.bind(program, GL_UNIFORM_BLOCK, "Params");
        lighting_.upload(&in.lighting.blocks, sizeof in.lighting.blocks, GL_STREAM_DRAW, "lighting parameter");
        lighting_.bind(program, GL_UNIFORM_BLOCK, "Lighting");
        // The block holds VX_MAX_VOLUMES whatever the count: the rest stays zero.
        std::vector<kernel::VxVolume> volumes(VX_MAX_VOLUMES);
        std::copy(in.volumes.begin(), in.volumes.end(), volumes.begin());
        volumes_.upload(volumes.data(), volumes.size() * sizeof(kernel::VxVolume), GL_STREAM_DRAW, "volume");
        volumes_.bind(program, GL_UNIFORM_BLOCK, "Volumes");
        const BrickAtlas& atlas = *in.atlas;
        const struct {
            GlBuffer& buffer;
            const char* block;
            const void* data;
            size_t bytes;
        } arrays[] = {
            {density_, "AtlasDensity", atlas.density.data(), atlas.density.size() * sizeof(float)},
            {emission_, "AtlasEmission", atlas.emission.data(), atlas.emission.size() * sizeof(float)},
            {pages_, "PageTable", in.pages->entries.data(), in.pages->entries.size() * sizeof(glm::ivec4)},
            {lights_, "Lights", in.lights.data(), in.lights.size() * sizeof(kernel::VxLight)},
            {tf_lut_, "TransferLut", in.tf_lut.data(), in.tf_lut.size() * sizeof(glm::vec4)},
            {emission_lut_, "EmissionLut", in.emission_lut.data(), in.emission_lut.size() * sizeof(glm::vec4)},
            {noise_, "Noise", in.noise.data(), in.noise.size() * sizeof(glm::vec4)},
        };
        for (const auto& a : arrays) {
            checkStorageSize(a.block, a.bytes);
            a.buffer.upload(a.data, a.bytes, GL_STATIC_DRAW, a.block);
            a.buffer.bind(program, GL_SHADER_STORAGE_BLOCK, a.block);
        }
        // The lighting methods' arrays (the kernel contract's), each bound even when its method is
        // off (GlBuffer's 16 zero bytes).
        for (size_t i = 0; i < kernel::CpuKernelData::kLightingArrays.size(); ++i) {
            const std::string block(kernel::CpuKernelData::kLightingArrays[i]);
            const auto given = std::find_if(in.lighting.arrays.begin(), in.lighting.arrays.end(),
                                            [&](const KernelArrayRef& a) { return a.block == block; });
            const void* data = given == in.lighting.arrays.end() ? nullptr : given->data;
            const size_t bytes = given == in.lighting.arrays.end() ? 0 : given->bytes;
            checkStorageSize(block.c_str(), bytes);
            lighting_arrays_[i].upload(data, bytes, GL_STATIC_DRAW, block);
            lighting_arrays_[i].bind(program, GL_SHADER_STORAGE_BLOCK, block.c_str());
        }
        // Colour, velocity, surface weight and the holdout depth share a block: llvmpipe allows a
        // compute program 16 storage blocks.
        const size_t color_bytes = atlas.color.size() * sizeof(float), velocity_bytes = atlas.velocity.size() * sizeof(float),
                     surface_bytes = atlas.surface.size() * sizeof(float),
                     holdout_bytes = in.holdout ? in.holdout->size() * sizeof(float) : 0;
        checkStorageSize("AtlasVectors", color_bytes + velocity_bytes + surface_bytes + holdout_bytes);
        vectors_.upload({{atlas.color.data(), color_bytes},
                         {atlas.velocity.data(), velocity_bytes},
                         {atlas.surface.data(), surface_bytes},
                         {in.holdout ? in.holdout->data() : nullptr, holdout_bytes}},
                        GL_STATIC_DRAW, "AtlasVectors");
        vectors_.bind(program, GL_SHADER_STORAGE_BLOCK, "AtlasVectors");

        const size_t row_bytes = size_t(img.width) * sizeof(kernel::VxPixel);
        // Deep samples: a fixed stride a pixel on the GPU, joined into the image's compact list;
        // their band holds fewer rows where a full one would pass the portable block size.
        const size_t deep_floats = deep_samples > 0 ? size_t(1 + 6 * deep_samples) : 1;
        const size_t deep_row_bytes = deep_samples > 0 ? size_t(img.width) * deep_floats * sizeof(float) : sizeof(float);
        const int band_rows = std::max(1, std::min({kBandRows, img.height, int(kDeepBandBytes / deep_row_bytes)}));
        checkStorageSize("Band", row_bytes * band_rows);
        band_.upload(nullptr, row_bytes * band_rows, GL_STREAM_READ, "Band");
        band_.bind(program, GL_SHADER_STORAGE_BLOCK, "Band");
        checkStorageSize("DeepBand", deep_row_bytes * band_rows);
        deep_band_.upload(nullptr, deep_row_bytes * (deep_samples > 0 ? band_rows : 1), GL_STREAM_READ, "DeepBand");
        deep_band_.bind(program, GL_SHADER_STORAGE_BLOCK, "DeepBand");
        std::vector<float> deep_rows(deep_samples > 0 ? deep_row_bytes / sizeof(float) * band_rows : 0);
        if (deep_samples > 0) img.deep.counts.resize(img.pixels.size());

        // Under motion blur a pixel's rays are dispatched one at a time and averaged here by the
        // kernel's own running mean, so that no invocation runs longer than one ray's march.
        const int rays = in.params.time_samples;
        kernel::CpuKernelData mean_of = rays > 1 ? bindKernelData(in) : kernel::CpuKernelData{};
        std::vector<kernel::VxPixel> ray_band(rays > 1 ? size_t(img.width) * band_rows : 0);
        std::vector<float> alpha_sums(ray_band.size());
        // Only the render region's rows are dispatched; its columns are kept from them below.
        const glm::ivec4 region = in.region;
        const kernel::VxPixel empty = kernel::CpuKernelData{}.vx_empty_pixel();
        const auto outside = [&](size_t p) { const int x = int(p % size_t(img.width)); return x < region.x || x >= region.z; };
        std::fill(img.pixels.begin(), img.pixels.end(), empty);
        glUseProgram(program);
        for (int y0 = region.y; y0 < region.w; y0 += band_rows) {
            const int rows = std::min(band_rows, region.w - y0);
            kernel::VxPixel* band_pixels = &img.pixels[size_t(y0) * img.width];
            glProgramUniform1i(program, row_offset, y0);
            for (int ray = 0; ray < rays; ++ray) {
                glProgramUniform1i(program, ray_uniform, ray);
                glDispatchCompute(GLuint((img.width + kGroupSize - 1) / kGroupSize),
                                  GLuint((rows + kGroupSize - 1) / kGroupSize), 1);
                // Reading the band back waits for the dispatch, so only one band is ever in flight.
                glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
                glGetNamedBufferSubData(band_.id(), 0, GLsizeiptr(row_bytes * rows), ray == 0 ? band_pixels : ray_band.data());
                for (size_t p = 0; rays > 1 && p < size_t(img.width) * rows; ++p) {
                    if (ray == 0) alpha_sums[p] = band_pixels[p].rgba.w;
                    else mean_of.vx_pixel_mean_add(band_pixels[p], ray_band[p], ray + 1, alpha_sums[p]);
                }
            }
            for (size_t p = 0; p < size_t(img.width) * rows; ++p)
                if (outside(p)) band_pixels[p] = empty;
            if (deep_samples == 0) continue;
            glGetNamedBufferSubData(deep_band_.id(), 0, GLsizeiptr(deep_row_bytes * rows), deep_rows.data());
            for (size_t p = 0; p < size_t(img.width) * rows; ++p) {
                const float* pixel = &deep_rows[p * deep_floats];
                const uint32_t count = outside(p) ? 0u : std::min(uint32_t(pixel[0]), uint32_t(deep_samples));
                img.deep.counts[size_t(y0) * img.width + p] = count;
                for (uint32_t i = 0; i < count; ++i) {
                    const float* s = pixel + 1 + 6 * i;
                    kernel::VxDeepSample sample;
                    sample.rgb = glm::vec3(s[0], s[1], s[2]);
                    sample.alpha = s[3];
                    sample.z = s[4];
                    sample.z_back = s[5];
                    img.deep.samples.push_back(sample);
                }
            }
        }
        if (GLenum error = glGetError(); error != GL_NO_ERROR)
            throw std::runtime_error("GL backend: the march failed with GL error " + std::to_string(error));
        return img;
    }

private:
    // The march program of a filter: one each, as the filter is a compile-time constant in GLSL
    // (shaders/vx_sample.h); with room in each ray for exactly the deep samples asked for
    // (vx_deep.h), as the array's size sets the program's cost; and with the march through several
    // volumes only for scenes of several (vx_march.h).
    static GLuint marchProgram(int filter, int deep_samples, bool several) {
        return kernelProgram("march.comp", std::string(filter == VX_FILTER_TRICUBIC ? "#define VX_ATLAS_FILTER VX_FILTER_TRICUBIC\n" : "") +
                                               "#define VX_DEEP_CAPACITY " + std::to_string(deep_samples + 1) + "\n" +
                                               (several ? "#define VX_MARCH_VOLUMES 1\n" : ""));
    }

    const GlContextInfo& context_;
    GlBuffer params_, lighting_, density_, emission_, vectors_, pages_, lights_, tf_lut_, emission_lut_, noise_, volumes_, band_, deep_band_;
    std::array<GlBuffer, kernel::CpuKernelData::kLightingArrays.size()> lighting_arrays_;
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
