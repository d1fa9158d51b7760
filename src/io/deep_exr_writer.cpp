#include "io/deep_exr_writer.h"

#include <half.h>
#include <ImfChannelList.h>
#include <ImfDeepFrameBuffer.h>
#include <ImfDeepScanLineOutputFile.h>
#include <ImfPartType.h>

#include <array>
#include <stdexcept>

#include "io/exr_common.h"

namespace voxlux {
namespace {

Imf::Compression deepCompression(const std::string& name) {
    const Imf::Compression c = exrCompression(name);
    const bool allowed = c == Imf::NO_COMPRESSION || c == Imf::RLE_COMPRESSION || c == Imf::ZIPS_COMPRESSION;
    return allowed ? c : Imf::ZIPS_COMPRESSION;
}

}  // namespace

ExrWriteReport writeDeepExr(const std::string& path, const RenderImage& img, const OutputSpec& spec, const ExrMetadata& meta) {
    const DeepSamples& deep = img.deep;
    const size_t pixels = size_t(img.width) * img.height, n = deep.samples.size();
    size_t counted = 0;
    for (uint32_t c : deep.counts) counted += c;
    if (deep.counts.size() != pixels || counted != n)
        throw std::logic_error("deep image: " + std::to_string(deep.counts.size()) + " sample counts for " + std::to_string(pixels) +
                               " pixels, adding up to " + std::to_string(counted) + " of " + std::to_string(n) + " samples");
    const bool half = spec.pixel_type == PixelType::Half;
    ExrWriteReport report;

    // One array a channel, holding every pixel's samples in order; each pixel points into it.
    const std::array<const char*, 6> names{"R", "G", "B", "A", "Z", "ZBack"};
    std::array<std::vector<float>, 6> values;
    for (auto& v : values) v.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const kernel::VxDeepSample& s = deep.samples[i];
        const float channel[6] = {s.rgb.x, s.rgb.y, s.rgb.z, s.alpha, s.z, s.z_back};
        for (int c = 0; c < 6; ++c) values[c][i] = exrStorable(channel[c], half && c < 4, report);
    }
    std::array<std::vector<Imath::half>, 4> halves;
    std::array<std::vector<char*>, 6> pointers;
    Imf::Header header = voxluxExrHeader(img.width, img.height, meta);
    header.setType(Imf::DEEPSCANLINE);
    header.compression() = deepCompression(spec.compression);
    Imf::DeepFrameBuffer fb;
    std::vector<unsigned int> counts(deep.counts.begin(), deep.counts.end());
    fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()), sizeof(unsigned int),
                                         sizeof(unsigned int) * img.width));
    for (int c = 0; c < 6; ++c) {
        const bool as_half = half && c < 4;
        if (as_half) halves[c].assign(values[c].begin(), values[c].end());
        char* base = as_half ? reinterpret_cast<char*>(halves[c].data()) : reinterpret_cast<char*>(values[c].data());
        const size_t stride = as_half ? sizeof(Imath::half) : sizeof(float);
        pointers[c].resize(pixels);
        size_t offset = 0;
        for (size_t p = 0; p < pixels; ++p) {
            pointers[c][p] = base + offset * stride;
            offset += deep.counts[p];
        }
        const Imf::PixelType type = as_half ? Imf::HALF : Imf::FLOAT;
        header.channels().insert(names[c], Imf::Channel(type));
        fb.insert(names[c], Imf::DeepSlice(type, reinterpret_cast<char*>(pointers[c].data()), sizeof(char*), sizeof(char*) * img.width, stride));
    }
    writeAtomically(path, [&](const std::string& tmp) {
        Imf::DeepScanLineOutputFile file(tmp.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(img.height);
    });
    return report;
}

}  // namespace voxlux
