#include "scan/raw_reader.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/error.h"

namespace voxlux {
namespace {

size_t bytesOf(RawType t) { return t == RawType::U8 ? 1 : t == RawType::F32 ? 4 : 2; }
const char* nameOf(RawType t) {
    switch (t) {
        case RawType::U8: return "u8";
        case RawType::U16: return "u16";
        case RawType::I16: return "i16";
        case RawType::F32: return "f32";
    }
    return "?";
}

template <typename T>
T loadAs(const unsigned char* p, bool swap) {
    std::array<unsigned char, sizeof(T)> b;
    std::memcpy(b.data(), p, sizeof(T));
    if (swap) std::reverse(b.begin(), b.end());
    return std::bit_cast<T>(b);
}

class RawReader : public ScanReader {
public:
    RawReader(std::string file, const RawLayout& layout, const std::string& format)
        : file_(std::move(file)), layout_(layout), in_(file_, std::ios::binary) {
        if (!in_) throw InputError(file_ + ": cannot open");
        info_.source = file_;
        info_.dims = layout.dims;
        info_.format = format;
        info_.index_to_world = glm::dmat4(1.0);
        for (int a = 0; a < 3; ++a) info_.index_to_world[a][a] = layout.spacing[a];
        slice_.resize(size_t(layout.dims.x) * size_t(layout.dims.y) * bytesOf(layout.type));
    }

    void readSlice(int k, float* out) override {
        in_.clear();
        in_.seekg(std::streamoff(layout_.header_bytes + std::uint64_t(k) * slice_.size()));
        if (!in_.read(reinterpret_cast<char*>(slice_.data()), std::streamsize(slice_.size())))
            throw InputError(file_ + ": cannot read slice " + std::to_string(k));
        const bool swap = layout_.big_endian != (std::endian::native == std::endian::big);
        const size_t n = size_t(layout_.dims.x) * size_t(layout_.dims.y);
        const unsigned char* p = slice_.data();
        for (size_t i = 0; i < n; ++i) switch (layout_.type) {
                case RawType::U8: out[i] = float(p[i]); break;
                case RawType::U16: out[i] = float(loadAs<std::uint16_t>(p + 2 * i, swap)); break;
                case RawType::I16: out[i] = float(loadAs<std::int16_t>(p + 2 * i, swap)); break;
                case RawType::F32: out[i] = loadAs<float>(p + 4 * i, swap); break;
            }
    }

private:
    std::string file_;
    RawLayout layout_;
    std::ifstream in_;
    std::vector<unsigned char> slice_;
};

}  // namespace

std::optional<RawType> rawTypeNamed(const std::string& name) {
    for (RawType t : {RawType::U8, RawType::U16, RawType::I16, RawType::F32})
        if (name == nameOf(t)) return t;
    return std::nullopt;
}

// VolPack's .den header: short version (1); short orig_min[3], orig_max[3], orig_len[3],
// extr_min[3], extr_max[3], extr_len[3], map_min[3], map_max[3], map_len[3]; short map_warps;
// int map_length (voxels), in the writing machine's byte order.
std::optional<RawLayout> denLayout(const std::string& file) {
    constexpr size_t kHeader = 62;
    std::ifstream in(file, std::ios::binary);
    std::array<unsigned char, kHeader> h{};
    if (!in.read(reinterpret_cast<char*>(h.data()), kHeader)) return std::nullopt;
    for (bool big : {false, true}) {
        const bool swap = big != (std::endian::native == std::endian::big);
        if (loadAs<std::int16_t>(h.data(), swap) != 1) continue;
        RawLayout layout;
        for (int a = 0; a < 3; ++a) layout.dims[a] = loadAs<std::int16_t>(h.data() + 50 + 2 * a, swap);
        const std::int32_t voxels = loadAs<std::int32_t>(h.data() + 58, swap);
        if (glm::any(glm::lessThanEqual(layout.dims, glm::ivec3(0))) ||
            std::int64_t(layout.dims.x) * layout.dims.y * layout.dims.z != voxels)
            continue;
        layout.header_bytes = kHeader;
        layout.big_endian = big;
        return layout;
    }
    return std::nullopt;
}

std::unique_ptr<ScanReader> openRaw(const std::string& file, const RawLayout& layout, const std::string& format) {
    if (glm::any(glm::lessThanEqual(layout.dims, glm::ivec3(0))))
        throw InputError(file + ": a raw volume needs --dims X,Y,Z, each at least 1");
    if (glm::any(glm::lessThanEqual(layout.spacing, glm::dvec3(0.0))) ||
        !std::isfinite(layout.spacing.x + layout.spacing.y + layout.spacing.z))
        throw InputError(file + ": --spacing must be positive");
    if (double(layout.dims.x) * double(layout.dims.y) * double(layout.dims.z) > kMaxScanVoxels)
        throw InputError(file + ": --dims " + std::to_string(layout.dims.x) + "," + std::to_string(layout.dims.y) + "," +
                         std::to_string(layout.dims.z) + " is more than the 2^34 voxels voxlux imports");
    const std::uint64_t voxels = std::uint64_t(layout.dims.x) * std::uint64_t(layout.dims.y) * std::uint64_t(layout.dims.z);
    const std::uint64_t expected = layout.header_bytes + voxels * bytesOf(layout.type);
    const std::uint64_t size = std::filesystem::file_size(file);
    if (size != expected)
        throw InputError(file + ": " + (size < expected ? "truncated" : "larger than its layout") + ": " +
                         std::to_string(layout.dims.x) + "x" + std::to_string(layout.dims.y) + "x" +
                         std::to_string(layout.dims.z) + " " + nameOf(layout.type) + " voxels after " +
                         std::to_string(layout.header_bytes) + " header bytes need " + std::to_string(expected) +
                         " bytes, the file has " + std::to_string(size));
    return std::make_unique<RawReader>(file, layout, format);
}

}  // namespace voxlux
