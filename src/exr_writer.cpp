#include "exr_writer.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include <unistd.h>

#include <half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <ImfFloatAttribute.h>
#include <ImfIntAttribute.h>

#include "error.h"

namespace voxlux {
namespace fs = std::filesystem;

namespace {

Imf::Compression compressionOf(const std::string& name) {
    if (name == "none") return Imf::NO_COMPRESSION;
    if (name == "zips") return Imf::ZIPS_COMPRESSION;
    if (name == "piz") return Imf::PIZ_COMPRESSION;
    if (name == "dwaa") return Imf::DWAA_COMPRESSION;
    return Imf::ZIP_COMPRESSION;
}

Imath::M44f toImath(const glm::mat4& m) {
    Imath::M44f out;  // Imath multiplies row vectors; glm's m[c][r] holds the same numbers
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out[i][j] = m[i][j];
    return out;
}

struct Channel {
    std::string name;
    Imf::PixelType type;
    std::vector<float> plane;
    std::vector<Imath::half> half_plane;  // filled from `plane` for HALF channels
};

std::string temporaryPathFor(const std::string& path) {
    fs::path p(path);
    return (p.parent_path() / ("." + p.filename().string() + ".tmp-" + std::to_string(::getpid()))).string();
}

}  // namespace

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    const std::string tmp = temporaryPathFor(path);
    std::error_code ec;
    try {
        write(tmp);
    } catch (const std::exception& e) {
        fs::remove(tmp, ec);
        throw InputError(path + ": cannot write (" + e.what() + ")");
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw InputError(path + ": cannot write (" + ec.message() + ")");
    }
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << bytes;
        if (!out.flush()) throw std::runtime_error("write failed");
    });
}

ExrWriteReport writeExr(const std::string& path, const RenderImage& img, const OutputSpec& spec,
                        const ExrMetadata& meta) {
    const size_t n = img.pixels.size();
    const Imf::PixelType colorType = spec.pixel_type == PixelType::Half ? Imf::HALF : Imf::FLOAT;
    auto wants = [&](const std::string& aov) {
        return std::find(spec.aovs.begin(), spec.aovs.end(), aov) != spec.aovs.end();
    };

    std::vector<Channel> channels;
    auto add = [&](const std::string& name, Imf::PixelType type, auto get) {
        Channel c{name, type, std::vector<float>(n), {}};
        for (size_t i = 0; i < n; ++i) c.plane[i] = get(img.pixels[i]);
        channels.push_back(std::move(c));
    };
    const char* rgb[] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) add(rgb[k], colorType, [k](const kernel::VxPixel& p) { return p.rgba[k]; });
    add("A", colorType, [](const kernel::VxPixel& p) { return p.rgba.w; });
    if (wants("direct"))
        for (int k = 0; k < 3; ++k)
            add(std::string("direct.") + rgb[k], colorType, [k](const kernel::VxPixel& p) { return p.direct[k]; });
    if (wants("indirect"))
        for (int k = 0; k < 3; ++k)
            add(std::string("indirect.") + rgb[k], colorType, [k](const kernel::VxPixel& p) { return p.indirect[k]; });
    if (wants("ambient"))
        for (int k = 0; k < 3; ++k)
            add(std::string("ambient.") + rgb[k], colorType, [k](const kernel::VxPixel& p) { return p.ambient[k]; });
    if (wants("emission"))
        for (int k = 0; k < 3; ++k)
            add(std::string("emission.") + rgb[k], colorType, [k](const kernel::VxPixel& p) { return p.emission[k]; });
    if (wants("transmittance"))
        add("transmittance.Y", colorType, [](const kernel::VxPixel& p) { return p.transmittance; });
    if (wants("depth"))  // depth keeps full float precision whatever the colour type
        add("depth.Z", Imf::FLOAT, [](const kernel::VxPixel& p) { return p.depth; });

    // No NaN or Inf reaches a file; half channels saturate instead of overflowing to Inf.
    ExrWriteReport report;
    constexpr float kHalfMax = 65504.0f;
    for (auto& c : channels)
        for (float& v : c.plane) {
            if (!std::isfinite(v)) {
                v = 0.0f;
                ++report.non_finite;
            } else if (c.type == Imf::HALF && std::abs(v) > kHalfMax) {
                v = std::copysign(kHalfMax, v);
                ++report.half_overflow;
            }
        }

    Imf::Header header(img.width, img.height);
    header.compression() = compressionOf(spec.compression);
    header.insert("voxlux/version", Imf::StringAttribute(VOXLUX_VERSION));
    header.insert("voxlux/sceneHash", Imf::StringAttribute(meta.scene_hash));
    if (meta.frame) header.insert("voxlux/frame", Imf::IntAttribute(*meta.frame));
    for (const auto& [stage, seconds] : meta.stage_seconds)
        header.insert("voxlux/seconds/" + stage, Imf::FloatAttribute(float(seconds)));
    Imf::addWorldToCamera(header, toImath(meta.world_to_camera));
    Imf::addWorldToNDC(header, toImath(meta.world_to_ndc));
    Imf::FrameBuffer fb;
    for (auto& c : channels) {
        header.channels().insert(c.name, Imf::Channel(c.type));
        if (c.type == Imf::HALF) {
            c.half_plane.assign(c.plane.begin(), c.plane.end());
            fb.insert(c.name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(c.half_plane.data()), sizeof(Imath::half),
                                         sizeof(Imath::half) * img.width));
        } else {
            fb.insert(c.name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(c.plane.data()), sizeof(float),
                                         sizeof(float) * img.width));
        }
    }

    writeAtomically(path, [&](const std::string& tmp) {
        Imf::OutputFile file(tmp.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(img.height);
    });
    return report;
}

}  // namespace voxlux
