// A .vdb file with a hostile length, count or offset is refused by the structure walk before
// OpenVDB reads it, and a short read inside a grid throws instead of leaving voxels unset. Each
// case patches a file written here (a box grid): header 57 bytes, file-metadata count at 57, grid
// count at 61, the first descriptor's name length at 65.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "test_support.h"
#include "volume/vdb_file.h"
#include "volume/vdb_loader.h"

namespace voxlux::test {
namespace {

std::string boxFileBytes(const std::string& path) {
    initOpenVdb();
    auto grid = boxGrid({0, 0, 0}, {15, 15, 15}, 0.5f);
    grid->setName("density");
    grid->insertMeta("temperature", openvdb::FloatMetadata(300.0f));
    openvdb::io::File(path).write({grid});
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `bytes` with a uint32 written at `offset`, saved to `path`.
std::string patched(const std::string& path, std::string bytes, size_t offset, uint32_t value) {
    std::memcpy(bytes.data() + offset, &value, sizeof value);
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

std::string openError(const std::string& path) {
    return inputErrorOf([&] { VdbFile f(path); for (size_t k = 0; k < f.grids().size(); ++k) f.read(k); });
}

TEST(VdbFile, ReadsWhatOpenVdbWrote) {
    const std::string path = tempDir("vdb_file") + "/box.vdb";
    boxFileBytes(path);
    VdbFile f(path);
    ASSERT_EQ(f.grids().size(), 1u);
    EXPECT_EQ(f.grids()[0].name, "density");
    EXPECT_EQ(f.grids()[0].value_type, "float");
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(f.read(0));
    EXPECT_EQ(grid->activeVoxelCount(), 16u * 16u * 16u);
    EXPECT_EQ(grid->metaValue<float>("temperature"), 300.0f);
}

TEST(VdbFile, HostileLengthsAndCountsAreRefusedBeforeOpenVdbReadsThem) {
    const std::string dir = tempDir("vdb_file");
    const std::string bytes = boxFileBytes(dir + "/box.vdb");
    const std::string size = std::to_string(bytes.size());
    // A name length of 3.6e9 had OpenVDB allocate and clear 3.6 GB (fuzz_vdb found it).
    EXPECT_EQ(openError(patched(dir + "/name.vdb", bytes, 65, 0xdadadadau)),
              dir + "/name.vdb: truncated: grid name needs 3671775962 bytes at byte 69 but the file has " + size);
    // 4e9 metadata items on a short file: OpenVDB loops reading nothing.
    // (The bytes that follow are read as a name; a byte that is not printable is written \xHH.)
    EXPECT_EQ(openError(patched(dir + "/count.vdb", bytes, 57, 0xffffffffu)),
              dir + "/count.vdb: truncated: file metadata '\\x07' type needs 1677721600 bytes at byte 70 but the file has " + size);
    EXPECT_EQ(openError(patched(dir + "/grids.vdb", bytes, 61, 0x80000000u)),
              dir + "/grids.vdb: damaged: negative grid count -2147483648");
    EXPECT_EQ(openError(patched(dir + "/magic.vdb", bytes, 0, 0)), dir + "/magic.vdb: not an OpenVDB file (no VDB magic number)");
    EXPECT_EQ(openError(patched(dir + "/version.vdb", bytes, 8, 9999)),
              dir + "/version.vdb: OpenVDB file format 9999 is not supported (221 to " + std::to_string(openvdb::OPENVDB_FILE_VERSION) + ")");
}

TEST(VdbFile, AFloatMetadataOfTheWrongSizeIsRefused) {
    const std::string dir = tempDir("vdb_file");
    std::string bytes = boxFileBytes(dir + "/box.vdb");
    // The grid's "temperature" item: its type name "float", then its size (4).
    const size_t type = bytes.find(std::string("\x05\0\0\0float", 9), bytes.find("temperature"));
    ASSERT_NE(type, std::string::npos);
    EXPECT_EQ(openError(patched(dir + "/meta.vdb", bytes, type + 9, 1000)),
              dir + "/meta.vdb: damaged: grid 'density' metadata 'temperature' (float) has 1000 bytes");
}

// A file cut short anywhere is refused; before, OpenVDB read it with exit 0 and part of its voxels.
TEST(VdbFile, AFileCutShortIsRefusedWhereverItIsCut) {
    const std::string dir = tempDir("vdb_file");
    const std::string bytes = boxFileBytes(dir + "/box.vdb");
    for (size_t length : {size_t(3), size_t(40), size_t(70), bytes.size() / 2, bytes.size() - 1}) {
        const std::string path = dir + "/cut.vdb";
        std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(length));
        const std::string error = openError(path);
        if (length < 8) EXPECT_EQ(error, path + ": not an OpenVDB file (no VDB magic number)");
        else EXPECT_EQ(error.rfind(path + ": truncated: ", 0), 0u) << length << ": " << error;
    }
}

// A count inside a grid's tree that runs past the file (a root tile count of 4e9, as fuzz_vdb
// found) is a short read, which throws: before, OpenVDB looped on it.
TEST(VdbFile, AShortReadInsideAGridIsRefused) {
    const std::string dir = tempDir("vdb_file");
    const std::string bytes = boxFileBytes(dir + "/box.vdb");
    // The root's topology: buffer count 1, background 0, 0 tiles, 1 child.
    const std::string root("\1\0\0\0\0\0\0\0\0\0\0\0\1\0\0\0", 16);
    const size_t at = bytes.find(root);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes.find(root, at + 1), std::string::npos);
    EXPECT_EQ(openError(patched(dir + "/tiles.vdb", bytes, at + 8, 0xffffffffu)),
              dir + "/tiles.vdb: damaged: grid 'density' reads past the end of the file (a count or size in its tree is wrong)");
}

// A zero scale in the grid's transform: OpenVDB's getAffineMap() aborted the process on it
// (fuzz_vdb found it); the loader refuses the grid.
TEST(VdbFile, ASingularTransformIsRefusedNotAnAbort) {
    const std::string dir = tempDir("vdb_file");
    std::string bytes = boxFileBytes(dir + "/box.vdb");
    const size_t map = bytes.find("UniformScaleMap");
    ASSERT_NE(map, std::string::npos);
    std::fill_n(bytes.begin() + std::ptrdiff_t(map + 15), 24, '\0');   // its three scale values
    const std::string path = dir + "/zero_scale.vdb";
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
    EXPECT_EQ(inputErrorOf([&] { loadVolume(path, VolumeSpec{}); }),
              path + ": grid 'density' has a singular index-to-world transform");
}

}  // namespace
}  // namespace voxlux::test
