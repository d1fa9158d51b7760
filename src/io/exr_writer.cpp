#include "io/exr_writer.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>

#include <signal.h>
#include <unistd.h>

#include <half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include "core/error.h"
#include "io/exr_common.h"

namespace voxlux {
namespace fs = std::filesystem;

namespace {

Imf::PixelType imfType(PixelType t) { return t == PixelType::Half ? Imf::HALF : Imf::FLOAT; }

// Depth keeps full float precision unless its AOV asks otherwise; other layers follow the output.
Imf::PixelType layerType(const OutputSpec& spec, const AovSpec& aov) {
    if (aov.pixel_type) return imfType(*aov.pixel_type);
    return aov.name == "depth" ? Imf::FLOAT : imfType(spec.pixel_type);
}

struct Channel {
    std::string name;
    Imf::PixelType type;
    std::vector<float> plane;
    std::vector<Imath::half> half_plane;  // filled from `plane` for HALF channels
};

// The status of an output path, refused when it is a folder: no write may replace one.
fs::file_status refuseFolder(const std::string& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (fs::is_directory(status)) throw InputError(path + ": is a folder, not a file");
    return status;
}

std::string temporaryPrefixFor(const std::string& path) { return "." + fs::path(path).filename().string() + ".tmp-"; }

std::string temporaryPathFor(const std::string& path) {
    return (fs::path(path).parent_path() / (temporaryPrefixFor(path) + std::to_string(::getpid()))).string();
}

// Removes the temporaries a killed voxlux left for `path` (".<name>.tmp-<pid>" whose process no
// longer runs here). One pass over the folder per write.
void removeStaleTemporaries(const std::string& path) {
    const std::string prefix = temporaryPrefixFor(path);
    const fs::path folder = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        const std::string digits = name.substr(prefix.size());
        if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const pid_t pid = pid_t(std::stol(digits));
        if (pid != ::getpid() && ::kill(pid, 0) == -1 && errno == ESRCH) fs::remove(entry.path(), ec);
    }
}

// A folder's failure as the user reads it: "cannot write in folder /ro: Read-only file system".
std::string folderText(const fs::path& folder) { return folder.empty() ? std::string(".") : folder.string(); }

// Creates the empty temporary `tmp` for `path`, or throws naming `path`'s folder and the cause.
void createTemporary(const std::string& path, const std::string& tmp) {
    if (std::ofstream(tmp, std::ios::binary)) return;
    const int cause = errno;
    throw InputError(path + ": cannot write in folder " + folderText(fs::path(path).parent_path()) + ": " + std::strerror(cause));
}

}  // namespace

std::optional<std::string> outputProblem(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) return path + ": is a folder, not a file";
    const fs::path parent = fs::path(path).parent_path();
    fs::path existing = parent.empty() ? fs::path(".") : parent;
    while (!fs::exists(existing, ec) && existing != "." && existing.has_relative_path())
        existing = existing.parent_path().empty() ? "." : existing.parent_path();
    const bool missing = existing != (parent.empty() ? fs::path(".") : parent);
    if (!fs::is_directory(existing, ec)) return path + ": cannot create folder " + folderText(parent) + ": " + std::strerror(ENOTDIR);
    const std::string verb = missing ? ": cannot create folder " : ": cannot write in folder ";
    if (::access(existing.c_str(), W_OK | X_OK) != 0) return path + verb + folderText(parent) + ": " + std::strerror(errno);
    return std::nullopt;
}

void makeOutputFolder(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (parent.empty() || fs::is_directory(parent, ec)) return;
    if (const auto problem = outputProblem(path)) throw InputError(*problem);
    fs::create_directories(parent, ec);
    if (ec) throw InputError(path + ": cannot create folder " + parent.string() + ": " + ec.message());
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    std::error_code ec;
    const fs::file_status target = refuseFolder(path);
    if (fs::exists(target) && !fs::is_regular_file(target)) {
        // A device or a pipe (/dev/null, a FIFO) is written in place: a rename would replace it.
        try {
            write(path);
        } catch (const std::exception& e) {
            throw InputError(path + ": cannot write (" + e.what() + ")");
        }
        return;
    }
    removeStaleTemporaries(path);
    const std::string tmp = temporaryPathFor(path);
    createTemporary(path, tmp);   // a folder that takes no file is named as such, before a writer names the temporary
    try {
        write(tmp);
    } catch (const std::exception& e) {
        fs::remove(tmp, ec);
        std::string problem = e.what();
        for (size_t at = problem.find(tmp); at != std::string::npos; at = problem.find(tmp, at + path.size()))
            problem.replace(at, tmp.size(), path);
        throw InputError(path + ": cannot write (" + problem + ")");
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        const std::string problem = ec.message();  // before the clean-up reuses ec
        fs::remove(tmp, ec);
        throw InputError(path + ": cannot write (" + problem + ")");
    }
}

void checkWritable(const std::string& path) {
    refuseFolder(path);
    makeOutputFolder(path);
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) return;   // a device, written in place
    const std::string probe = temporaryPathFor(path);
    createTemporary(path, probe);
    fs::remove(probe, ec);
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        errno = 0;
        out << bytes;
        if (!out.flush()) throw std::runtime_error(errno ? std::strerror(errno) : "write failed");
    });
}

ExrWriteReport writeExr(const std::string& path, const RenderImage& img, const OutputSpec& spec,
                        const ExrMetadata& meta, const std::vector<ExrPlane>& coverage) {
    const size_t n = img.pixels.size();
    std::vector<Channel> channels;
    auto add = [&](const std::string& name, Imf::PixelType type, auto get) {
        Channel c{name, type, std::vector<float>(n), {}};
        for (size_t i = 0; i < n; ++i) c.plane[i] = get(img.pixels[i]);
        channels.push_back(std::move(c));
    };
    const char* rgb[] = {"R", "G", "B"};
    // A layer's R, G and B: rgbOf(i) is pixel i's colour.
    auto addLayer = [&](const std::string& prefix, Imf::PixelType type, auto rgbOf) {
        for (int k = 0; k < 3; ++k) {
            Channel c{prefix + rgb[k], type, std::vector<float>(n), {}};
            for (size_t i = 0; i < n; ++i) c.plane[i] = rgbOf(i)[k];
            channels.push_back(std::move(c));
        }
    };
    auto addRgb = [&](const std::string& prefix, Imf::PixelType type, auto member) {
        addLayer(prefix, type, [&](size_t i) { return glm::vec3(img.pixels[i].*member); });
    };
    const Imf::PixelType colorType = imfType(spec.pixel_type);
    addRgb("", colorType, &kernel::VxPixel::rgba);
    add("A", colorType, [](const kernel::VxPixel& p) { return p.rgba.w; });
    for (const AovSpec& aov : spec.aovs) {
        const Imf::PixelType type = layerType(spec, aov);
        if (aov.name == "direct") addRgb("direct.", type, &kernel::VxPixel::direct);
        if (aov.name == "indirect") addRgb("indirect.", type, &kernel::VxPixel::indirect);
        if (aov.name == "ambient") addRgb("ambient.", type, &kernel::VxPixel::ambient);
        if (aov.name == "emission") addRgb("emission.", type, &kernel::VxPixel::emission);
        // OpenEXR names a lone grey channel Y (luminance): viewers show the layer as grey.
        if (aov.name == "transmittance") add("transmittance.Y", type, [](const kernel::VxPixel& p) { return p.transmittance; });
        if (aov.name == "depth") add("depth.Z", type, [](const kernel::VxPixel& p) { return p.depth; });
        if (aov.name == "variance") add("variance.Y", type, [](const kernel::VxPixel& p) { return p.variance; });
        if (aov.name == "coverage")
            for (const ExrPlane& plane : coverage) channels.push_back({"coverage." + plane.name, type, *plane.values, {}});
        if (aov.name == "light_groups")
            for (const LightGroupLayer& layer : img.light_groups)
                addLayer("lightgroup." + layer.name + ".", type, [&](size_t i) { return layer.rgb[i]; });
    }

    ExrWriteReport report;
    for (auto& c : channels)
        for (float& v : c.plane) v = exrStorable(v, c.type == Imf::HALF, report);

    Imf::Header header = voxluxExrHeader(img.width, img.height, meta);
    header.compression() = exrCompression(spec.compression);
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
