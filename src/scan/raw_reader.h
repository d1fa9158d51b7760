// Raw voxel files: a header of known length, then X*Y*Z values of one type, i fastest. VolPack's
// .den (Levoy's format: a 62-byte header of shorts, then 8-bit voxels) is recognised by its header,
// so it needs no layout. Reading a slice is one seek and one read; nothing else is held.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "scan/scan_reader.h"

namespace voxlux {

enum class RawType { U8, U16, I16, F32 };

struct RawLayout {
    glm::ivec3 dims{0};
    RawType type = RawType::U8;
    glm::dvec3 spacing{1.0};           // voxel edge along i, j, k, world units
    std::uint64_t header_bytes = 0;
    bool big_endian = false;
};

// "u8" -> U8, ...; nothing for another name.
std::optional<RawType> rawTypeNamed(const std::string& name);

// The layout in a VolPack .den header, or nothing when `file` does not start with one.
std::optional<RawLayout> denLayout(const std::string& file);

// `file` is a regular file (openScan checks). Checks that it holds exactly header + X*Y*Z values; throws InputError naming the file,
// the bytes expected and the bytes it has.
std::unique_ptr<ScanReader> openRaw(const std::string& file, const RawLayout& layout, const std::string& format);

}  // namespace voxlux
