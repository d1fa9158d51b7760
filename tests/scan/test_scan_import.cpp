// voxlux import: each format's voxels land where the file puts them, with the file's values,
// and only the voxels above the background are active. The NIfTI and DICOM files are written here
// with the formats' own libraries (libnifti2, DCMTK), so the geometry is known exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>
#include <nifti2_io.h>
#include <nlohmann/json.hpp>

#include "scan/scan_import.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<ScanReader> open(const std::string& input, const ImportOptions& options = {}) {
    std::vector<std::string> skipped;
    return openScan(input, options, skipped);
}

openvdb::FloatGrid::Ptr gridOf(const std::string& input, ImportOptions options = {}) {
    initOpenVdb();
    ImportReport report;
    auto reader = open(input, options);
    return buildScanGrid(*reader, options, report);
}

// Index and value of the grid's largest active voxel.
std::pair<openvdb::Coord, float> brightest(const openvdb::FloatGrid& grid) {
    std::pair<openvdb::Coord, float> best{openvdb::Coord(), -1e30f};
    for (auto it = grid.cbeginValueOn(); it; ++it)
        if (*it > best.second) best = {it.getCoord(), *it};
    return best;
}

glm::dvec3 worldOf(const openvdb::FloatGrid& grid, const openvdb::Coord& c) {
    const openvdb::Vec3d w = grid.indexToWorld(c);
    return {w.x(), w.y(), w.z()};
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, const std::string& what) {
    EXPECT_LT(glm::length(a - b), 1e-4) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") against (" << b.x << ", "
                                        << b.y << ", " << b.z << ")";
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}
void writeBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// ---- raw and VolPack .den

TEST(ScanImport, RawBigEndianWithAHeaderKeepsValuesAndSpacing) {
    const std::string dir = tempDir("scan_raw");
    const glm::ivec3 dims(5, 4, 3);
    std::string bytes(16, 'h');   // a 16-byte header to skip
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const std::int16_t v = std::int16_t(-500 + 100 * i + 10 * j + k);
                bytes += char((std::uint16_t(v) >> 8) & 0xff);
                bytes += char(std::uint16_t(v) & 0xff);
            }
    writeBytes(dir + "/ct.raw", bytes);
    ImportOptions options;
    options.raw = RawLayout{dims, RawType::I16, glm::dvec3(0.5, 0.75, 2.0), 16, true};
    options.background = -1e9f;
    const auto grid = gridOf(dir + "/ct.raw", options);
    EXPECT_EQ(grid->activeVoxelCount(), 60u);
    auto acc = grid->getConstAccessor();
    EXPECT_EQ(acc.getValue(openvdb::Coord(0, 0, 0)), -500.0f);
    EXPECT_EQ(acc.getValue(openvdb::Coord(4, 3, 2)), -500.0f + 400 + 30 + 2);
    expectNear(worldOf(*grid, openvdb::Coord(4, 3, 2)), glm::dvec3(2.0, 2.25, 4.0), "voxel (4, 3, 2)");
}

// A .den written here: the header VolPack's makevolume writes, little-endian, then 8-bit voxels.
std::string denFile(const glm::ivec3& dims, const std::vector<unsigned char>& voxels) {
    std::array<std::int16_t, 29> h{};
    h[0] = 1;
    for (int a = 0; a < 3; ++a) h[25 + a] = std::int16_t(dims[a]);   // map_len
    std::string bytes(reinterpret_cast<const char*>(h.data()), 58);
    const std::int32_t n = dims.x * dims.y * dims.z;
    bytes.append(reinterpret_cast<const char*>(&n), 4);
    bytes.append(voxels.begin(), voxels.end());
    return bytes;
}

TEST(ScanImport, DenIsRecognisedByItsHeader) {
    const std::string dir = tempDir("scan_den");
    std::vector<unsigned char> voxels(6 * 5 * 4, 0);
    voxels[(3 * 5 + 2) * 6 + 1] = 77;   // (1, 2, 3)
    writeBytes(dir + "/small.den", denFile({6, 5, 4}, voxels));
    auto reader = open(dir + "/small.den");
    EXPECT_EQ(reader->info().format, "VolPack .den");
    EXPECT_EQ(reader->info().dims, glm::ivec3(6, 5, 4));
    const auto grid = gridOf(dir + "/small.den");
    EXPECT_EQ(grid->activeVoxelCount(), 1u);
    EXPECT_EQ(brightest(*grid).first, openvdb::Coord(1, 2, 3));
    EXPECT_EQ(brightest(*grid).second, 77.0f);
}

// Counts of each byte value among the head's voxels.
std::array<std::uint64_t, 256> byteHistogram(const std::string& den) {
    const std::string bytes = readBytes(den);
    std::array<std::uint64_t, 256> h{};
    for (size_t i = 62; i < bytes.size(); ++i) ++h[static_cast<unsigned char>(bytes[i])];
    return h;
}

TEST(ScanImportShared, HeadImportsWithItsHistogramAndOnlyTissueActive) {
    VOXLUX_REQUIRE_SHARED(den, "scan/brainsmall.den");
    ImportReport report;
    initOpenVdb();
    auto reader = open(den);
    const auto grid = buildScanGrid(*reader, {}, report);
    EXPECT_EQ(report.info.dims, glm::ivec3(128, 128, 84));
    EXPECT_EQ(report.min_value, 0.0f);
    EXPECT_EQ(report.max_value, 202.0f);
    const auto raw = byteHistogram(den);
    std::array<std::uint64_t, 256> imported{};
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        ASSERT_EQ(*it, std::floor(*it));
        imported[size_t(*it)] += it.getVoxelCount();
    }
    // The background (0, the minimum) is inactive; every other value is there as often as in the file.
    EXPECT_EQ(imported[0], 0u);
    EXPECT_EQ(grid->activeVoxelCount(), 128u * 128u * 84u - raw[0]);
    for (int v = 1; v < 256; ++v) EXPECT_EQ(imported[size_t(v)], raw[size_t(v)]) << "value " << v;
}

// The head inside a box 4 times its size along each axis, zeros around it: what a scanner's
// field of view around a small part looks like. The head starts on a whole 8^3 leaf, as in its own
// file, so that the grids differ by what the empty box costs, not by how the head's leaves
// straddle (an offset of half a leaf adds a layer of leaves along each face, about 10% here).
class PaddedReader : public ScanReader {
public:
    PaddedReader(ScanReader& inner, int factor) : inner_(inner), slice_(size_t(inner.info().dims.x) * inner.info().dims.y) {
        info_ = inner.info();
        offset_ = inner.info().dims * (factor - 1) / 2 / 8 * 8;
        info_.dims = inner.info().dims * factor;
    }
    void readSlice(int k, float* out) override {
        const glm::ivec3 in = inner_.info().dims;
        std::fill(out, out + size_t(info_.dims.x) * info_.dims.y, 0.0f);
        const int kk = k - offset_.z;
        if (kk < 0 || kk >= in.z) return;
        inner_.readSlice(kk, slice_.data());
        for (int j = 0; j < in.y; ++j)
            std::copy_n(slice_.data() + size_t(j) * in.x, in.x, out + size_t(j + offset_.y) * info_.dims.x + offset_.x);
    }

private:
    ScanReader& inner_;
    std::vector<float> slice_;
    glm::ivec3 offset_;
};

TEST(ScanImportShared, PaddingTheHeadGrowsItsGridByUnderTenPercent) {
    VOXLUX_REQUIRE_SHARED(den, "scan/brainsmall.den");
    initOpenVdb();
    ImportReport plain_report, padded_report;
    auto reader = open(den);
    const auto plain = buildScanGrid(*reader, {}, plain_report);
    PaddedReader padded(*reader, 4);
    const auto grid = buildScanGrid(padded, {}, padded_report);
    EXPECT_EQ(padded_report.voxels, 64 * plain_report.voxels);
    EXPECT_EQ(grid->activeVoxelCount(), plain->activeVoxelCount());
    const double growth = double(grid->memUsage()) / double(plain->memUsage());
    EXPECT_LT(growth, 1.10) << plain->memUsage() << " bytes, padded " << grid->memUsage();
}

// ---- NIfTI

enum class Orientation { Pixdim, Qform, Sform };

struct NiftiCase {
    int version;               // 1 or 2
    Orientation orientation;
    bool big_endian;
};

const glm::ivec3 kNiftiDims(7, 6, 5);
const openvdb::Coord kMarked(5, 1, 3);   // asymmetric: a flip or a swap of axes moves it

// Writes the case's file with libnifti: int16 voxels, value 1000 at kMarked, scl_slope 2,
// scl_inter -5. Returns the world position the file gives kMarked, computed here by hand.
glm::dvec3 writeNifti(const std::string& path, const NiftiCase& c) {
    const int64_t dims[8] = {3, kNiftiDims.x, kNiftiDims.y, kNiftiDims.z, 1, 1, 1, 1};
    nifti_image* nim = nifti_make_new_nim(dims, DT_INT16, 1);
    auto* data = static_cast<std::int16_t*>(nim->data);
    for (int i = 0; i < kNiftiDims.x * kNiftiDims.y * kNiftiDims.z; ++i) data[i] = std::int16_t(i % 17);
    data[(kMarked.z() * kNiftiDims.y + kMarked.y()) * kNiftiDims.x + kMarked.x()] = 1000;
    nim->scl_slope = 2.0;
    nim->scl_inter = -5.0;
    nim->dx = nim->pixdim[1] = 1.5;
    nim->dy = nim->pixdim[2] = 2.0;
    nim->dz = nim->pixdim[3] = 3.0;
    nim->qform_code = nim->sform_code = 0;
    const glm::dvec3 ijk(kMarked.x(), kMarked.y(), kMarked.z());
    glm::dvec3 world = ijk * glm::dvec3(1.5, 2.0, 3.0);
    if (c.orientation == Orientation::Qform) {
        // 90 degrees about z, qfac -1 (k flipped), offset (10, -20, 30): x = -dy j, y = dx i, z = -dz k.
        nim->qform_code = NIFTI_XFORM_SCANNER_ANAT;
        nim->quatern_b = 0.0;
        nim->quatern_c = 0.0;
        nim->quatern_d = std::sqrt(0.5);
        nim->qfac = -1.0;
        nim->qoffset_x = 10.0;
        nim->qoffset_y = -20.0;
        nim->qoffset_z = 30.0;
        world = glm::dvec3(10.0 - 2.0 * ijk.y, -20.0 + 1.5 * ijk.x, 30.0 - 3.0 * ijk.z);
    } else if (c.orientation == Orientation::Sform) {
        // An oblique, sheared sform; a different qform beside it, which the sform overrides.
        const double m[3][4] = {{0.9, 0.3, 0.1, -20.0}, {-0.2, 1.1, 0.4, 5.0}, {0.15, -0.1, 2.0, 12.0}};
        nim->sform_code = NIFTI_XFORM_ALIGNED_ANAT;
        nim->qform_code = NIFTI_XFORM_SCANNER_ANAT;
        nim->qoffset_x = 99.0;
        for (int r = 0; r < 4; ++r)
            for (int col = 0; col < 4; ++col) nim->sto_xyz.m[r][col] = r < 3 ? m[r][col] : col == 3 ? 1.0 : 0.0;
        for (int r = 0; r < 3; ++r) world[r] = m[r][0] * ijk.x + m[r][1] * ijk.y + m[r][2] * ijk.z + m[r][3];
    }
    // The header as libnifti makes it from the image; the file is that header, the 4-byte
    // extension flag, then the voxels (libnifti's own writer makes NIfTI-1 files only).
    nim->nifti_type = c.version == 2 ? NIFTI_FTYPE_NIFTI2_1 : NIFTI_FTYPE_NIFTI1_1;
    std::string header;
    if (c.version == 2) {
        nifti_2_header h;
        nifti_convert_nim2n2hdr(nim, &h);
        h.vox_offset = sizeof h + 4;
        header.assign(reinterpret_cast<const char*>(&h), sizeof h);
    } else {
        nifti_1_header h;
        nifti_convert_nim2n1hdr(nim, &h);
        h.vox_offset = float(sizeof h + 4);
        header.assign(reinterpret_cast<const char*>(&h), sizeof h);
    }
    std::string voxels(static_cast<const char*>(nim->data), size_t(nim->nvox) * size_t(nim->nbyper));
    nifti_image_free(nim);
    if (c.big_endian) {   // the header's fields and every voxel, byte-swapped
        swap_nifti_header(header.data(), c.version);
        for (size_t i = 0; i + 1 < voxels.size(); i += 2) std::swap(voxels[i], voxels[i + 1]);
    }
    const std::string bytes = header + std::string(4, '\0') + voxels;
    writeBytes(path, bytes);
    return world;
}

TEST(ScanImport, NiftiVoxelsLandWhereTheFilePutsThemInEveryOrientationAndByteOrder) {
    const std::string dir = tempDir("scan_nifti");
    for (int version : {1, 2})
        for (Orientation o : {Orientation::Pixdim, Orientation::Qform, Orientation::Sform})
            for (bool big : {false, true}) {
                const std::string name = "v" + std::to_string(version) + "_" + std::to_string(int(o)) + (big ? "_be" : "_le");
                SCOPED_TRACE(name);
                const std::string path = dir + "/" + name + ".nii";
                const glm::dvec3 expected = writeNifti(path, {version, o, big});
                auto reader = open(path);
                EXPECT_EQ(reader->info().format, version == 2 ? "NIfTI-2" : "NIfTI-1");
                EXPECT_EQ(reader->info().dims, kNiftiDims);
                const auto grid = gridOf(path);
                const auto [where, value] = brightest(*grid);
                EXPECT_EQ(where, kMarked);
                EXPECT_EQ(value, 1000.0f * 2.0f - 5.0f);   // scl_slope and scl_inter
                expectNear(worldOf(*grid, where), expected, "the marked voxel");
                // The minimum (0 * 2 - 5) is the background: inactive.
                EXPECT_EQ(grid->background(), -5.0f);
                EXPECT_EQ(grid->activeVoxelCount(), 7u * 6u * 5u - 13u);   // i % 17 == 0 at 0, 17, ..., 204
                // With an orientation the world is RAS, and the grid says so: head up +z, face +y.
                const std::string up = o == Orientation::Pixdim ? "" : "z", front = o == Orientation::Pixdim ? "" : "y";
                const auto meta = [&](const char* key) { return (*grid)[key] ? grid->metaValue<std::string>(key) : std::string(); };
                EXPECT_EQ(meta("up_axis"), up) << "(pixdim alone says nothing)";
                EXPECT_EQ(meta("front_axis"), front);
            }
}

// The importer writes the orientation it knows (or the user's --up and --front), and the quick
// form reads it: up is up in the frame, and the camera looks at the face, slightly from above.
TEST(ScanImport, TheOrientationFramesTheHeadUprightFromTheFront) {
    const std::string dir = tempDir("scan_orientation");
    std::vector<unsigned char> voxels(8 * 8 * 8, 0);
    for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = (i % 3) ? 50 : 0;
    writeBytes(dir + "/head.den", denFile({8, 8, 8}, voxels));
    ImportOptions options;
    options.up = "-y";
    options.front = "-x";
    importScan(dir + "/head.den", dir + "/head.vdb", options);
    const CliResult r = runCli("scene " + dir + "/head.vdb");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("voxlux: quick form: up axis -y (the grid's up_axis metadata; its front_axis -x faces the camera)"),
              std::string::npos) << r.err;
    const nlohmann::json camera = nlohmann::json::parse(r.out)["camera"];
    EXPECT_EQ(camera["up"], nlohmann::json::parse("[0.0, -1.0, 0.0]"));
    const glm::vec3 from(camera["position"][0].get<float>() - camera["look_at"][0].get<float>(),
                         camera["position"][1].get<float>() - camera["look_at"][1].get<float>(),
                         camera["position"][2].get<float>() - camera["look_at"][2].get<float>());
    const glm::vec3 toward = glm::normalize(from);
    EXPECT_LT(toward.x, -0.7f);   // in front of the face (-x)
    EXPECT_LT(toward.y, -0.1f);   // above it (-y is up)
    // The flags must name two different axes, and go together.
    const auto refused = [&](std::optional<std::string> up, std::optional<std::string> front) {
        ImportOptions o;
        o.up = up;
        o.front = front;
        return inputErrorOf([&] { importScan(dir + "/head.den", dir + "/bad.vdb", o); });
    };
    EXPECT_EQ(refused("z", std::nullopt), dir + "/head.den: --up and --front go together: the axis toward the head and the one toward the face");
    EXPECT_EQ(refused("z", "-z"), dir + "/head.den: --up z and --front -z must be different axes");
    EXPECT_EQ(refused("up", "y"), dir + "/head.den: --up and --front are axes: x, y, z, -x, -y or -z");
    EXPECT_FALSE(fs::exists(dir + "/bad.vdb"));
}

TEST(ScanImportShared, NibabelAnatomicalHasItsSizeAndSpacing) {
    VOXLUX_REQUIRE_SHARED(nii, "scan/nibabel_anatomical.nii");
    auto reader = open(nii);
    EXPECT_EQ(reader->info().format, "NIfTI-1");
    EXPECT_EQ(reader->info().dims, glm::ivec3(33, 41, 25));
    const auto grid = gridOf(nii);
    const openvdb::Vec3d voxel = grid->voxelSize();
    EXPECT_NEAR(voxel.x(), 2.0, 1e-6);
    EXPECT_NEAR(voxel.y(), 2.0, 1e-6);
    EXPECT_NEAR(voxel.z(), 2.0, 1e-6);
}

// ---- DICOM

const int kRows = 5, kColumns = 4;

struct DicomSlice {
    std::string series = "1.2.826.0.1.3680043.2.1125.1";
    std::string description = "Head";
    glm::dvec3 position{0.0};
    int rows = kRows, columns = kColumns;
    int high_bit = 11;            // 12 bits stored, ending here; the bits around them are set (overlays)
    bool has_position = true;     // a dose report's screenshot has none
};
const glm::dvec3 kRowDir(std::sqrt(0.75), 0.5, 0.0);   // oblique: 30 degrees about z
const glm::dvec3 kColumnDir(0.0, 0.0, -1.0);
const glm::dvec2 kPixelSpacing(0.75, 0.5);          // between rows, between columns

// Stored pixel of column i, row j, slice k: signed, 12 bits stored.
int storedPixel(int i, int j, int k) { return k == 3 && j == 1 && i == 2 ? 1500 : -300 + 37 * i - 11 * j + 5 * k; }

std::string numbersText(std::initializer_list<double> v) {
    std::string s;
    for (double x : v) {
        char b[32];
        std::snprintf(b, sizeof b, "%.10g", x);
        s += (s.empty() ? "" : "\\") + std::string(b);
    }
    return s;
}

void writeDicomSlice(const std::string& path, const DicomSlice& s, int k) {
    DcmFileFormat ff;
    DcmDataset* ds = ff.getDataset();
    char uid[100];
    ds->putAndInsertString(DCM_SOPClassUID, UID_CTImageStorage);
    ds->putAndInsertString(DCM_SOPInstanceUID, dcmGenerateUniqueIdentifier(uid, SITE_INSTANCE_UID_ROOT));
    ds->putAndInsertString(DCM_SeriesInstanceUID, s.series.c_str());
    ds->putAndInsertString(DCM_SeriesDescription, s.description.c_str());
    ds->putAndInsertString(DCM_Modality, "CT");
    ds->putAndInsertUint16(DCM_Rows, Uint16(s.rows));
    ds->putAndInsertUint16(DCM_Columns, Uint16(s.columns));
    ds->putAndInsertUint16(DCM_SamplesPerPixel, 1);
    ds->putAndInsertString(DCM_PhotometricInterpretation, "MONOCHROME2");
    ds->putAndInsertUint16(DCM_BitsAllocated, 16);
    ds->putAndInsertUint16(DCM_BitsStored, 12);
    ds->putAndInsertUint16(DCM_HighBit, Uint16(s.high_bit));
    ds->putAndInsertUint16(DCM_PixelRepresentation, 1);
    ds->putAndInsertString(DCM_PixelSpacing, numbersText({kPixelSpacing.x, kPixelSpacing.y}).c_str());
    ds->putAndInsertString(DCM_ImageOrientationPatient,
                           numbersText({kRowDir.x, kRowDir.y, kRowDir.z, kColumnDir.x, kColumnDir.y, kColumnDir.z}).c_str());
    if (s.has_position) ds->putAndInsertString(DCM_ImagePositionPatient, numbersText({s.position.x, s.position.y, s.position.z}).c_str());
    ds->putAndInsertString(DCM_RescaleSlope, "2");
    ds->putAndInsertString(DCM_RescaleIntercept, "-1024");
    std::vector<Uint16> pixels(size_t(s.rows * s.columns));
    const unsigned low = unsigned(s.high_bit - 11), others = 0xffffu & ~(0xfffu << low);
    for (int j = 0; j < s.rows; ++j)
        for (int i = 0; i < s.columns; ++i)
            pixels[size_t(j * s.columns + i)] = Uint16(((unsigned(storedPixel(i, j, k)) & 0xfffu) << low) | others);
    ds->putAndInsertUint16Array(DCM_PixelData, pixels.data(), pixels.size());
    ASSERT_TRUE(ff.saveFile(path.c_str(), EXS_LittleEndianExplicit).good()) << path;
}

const glm::dvec3 kNormal = glm::cross(kRowDir, kColumnDir);
const glm::dvec3 kFirst(-40.0, 25.0, 60.0);

// Six slices 1.25 mm apart along the normal, written in a shuffled order under shuffled names.
std::string writeSeries(const std::string& name) {
    const std::string dir = tempDir(name);
    const int order[6] = {4, 0, 5, 2, 1, 3};
    for (int n = 0; n < 6; ++n) {
        DicomSlice s;
        s.position = kFirst + 1.25 * double(order[n]) * kNormal;
        writeDicomSlice(dir + "/IM" + std::to_string(n) + ".dcm", s, order[n]);
    }
    writeBytes(dir + "/README.txt", "exported by a scanner\n");
    return dir;
}

TEST(ScanImport, DicomSeriesIsOrderedOrientedAndInHounsfieldUnits) {
    initOpenVdb();
    const std::string dir = writeSeries("scan_dicom");
    ImportOptions options;
    options.background = -1e9f;   // every voxel active, to compare them all
    ImportReport report;
    std::vector<std::string> skipped;
    auto reader = openScan(dir, options, skipped);
    EXPECT_EQ(skipped, std::vector<std::string>{"README.txt"});
    EXPECT_EQ(reader->info().dims, glm::ivec3(kColumns, kRows, 6));
    EXPECT_EQ(reader->info().modality, "CT");
    EXPECT_EQ(reader->info().units, "HU");
    const auto grid = buildScanGrid(*reader, options, report);
    auto acc = grid->getConstAccessor();
    for (int k = 0; k < 6; ++k)
        for (int j = 0; j < kRows; ++j)
            for (int i = 0; i < kColumns; ++i) {
                ASSERT_EQ(acc.getValue(openvdb::Coord(i, j, k)), float(storedPixel(i, j, k) * 2 - 1024)) << i << " " << j << " " << k;
                const glm::dvec3 lps = kFirst + double(i) * kPixelSpacing.y * kRowDir + double(j) * kPixelSpacing.x * kColumnDir +
                                       double(k) * 1.25 * kNormal;
                expectNear(worldOf(*grid, openvdb::Coord(i, j, k)), glm::dvec3(-lps.x, -lps.y, lps.z), "voxel");
            }
}

TEST(ScanImport, DicomFolderWithTwoSeriesIsRefusedNamingThem) {
    const std::string dir = tempDir("scan_dicom_mixed");
    for (int k = 0; k < 3; ++k) writeDicomSlice(dir + "/a" + std::to_string(k) + ".dcm", {.position = kFirst + double(k) * kNormal}, k);
    for (int k = 0; k < 2; ++k)
        writeDicomSlice(dir + "/b" + std::to_string(k) + ".dcm",
                        {.series = "1.2.826.0.1.3680043.2.1125.2", .description = "Bone", .position = kFirst + double(k) * kNormal}, k);
    EXPECT_EQ(inputErrorOf([&] { open(dir); }),
              dir + ": holds 2 series: 1.2.826.0.1.3680043.2.1125.1 (CT 'Head', 3 files), 1.2.826.0.1.3680043.2.1125.2 (CT 'Bone', 2 "
                    "files); put each series in a folder of its own");
}

TEST(ScanImport, DicomWithIrregularSliceSpacingIsRefused) {
    const std::string dir = tempDir("scan_dicom_gap");
    const double along[4] = {0.0, 1.0, 2.0, 4.0};
    for (int k = 0; k < 4; ++k) writeDicomSlice(dir + "/s" + std::to_string(k) + ".dcm", {.position = kFirst + along[k] * kNormal}, k);
    EXPECT_EQ(inputErrorOf([&] { open(dir); }),
              dir + ": the slice spacing is irregular: 2 mm between s2.dcm and s3.dcm, where the median gap is 1 mm; voxlux needs evenly "
                    "spaced slices (resample the series, or import its parts)");
}

// The 12 stored bits in bits 2..13, the others set (as overlays leave them): only HighBit says where.
TEST(ScanImport, DicomStoredBitsAreReadWhereHighBitPutsThem) {
    const std::string dir = tempDir("scan_dicom_high_bit");
    for (int k = 0; k < 2; ++k) writeDicomSlice(dir + "/s" + std::to_string(k) + ".dcm", {.position = kFirst + double(k) * kNormal, .high_bit = 13}, k);
    ImportOptions options;
    options.background = -1e9f;
    const auto grid = gridOf(dir, options);
    auto acc = grid->getConstAccessor();
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < kRows; ++j)
            for (int i = 0; i < kColumns; ++i) ASSERT_EQ(acc.getValue({i, j, k}), float(storedPixel(i, j, k) * 2 - 1024));
}

TEST(ScanImport, DicomFilesThatAreNotSlicesAreSkipped) {
    const std::string dir = writeSeries("scan_dicom_dose_report");
    writeDicomSlice(dir + "/dose.dcm", {.has_position = false}, 0);
    std::vector<std::string> skipped;
    auto reader = openScan(dir, {}, skipped);
    EXPECT_EQ(skipped, (std::vector<std::string>{"README.txt", "dose.dcm"}));
    EXPECT_EQ(reader->info().dims.z, 6);
}

// A real slice's pixels are more than the 4 KB the headers are read with: cut short, they are
// found missing when the slice is read.
TEST(ScanImport, DicomSliceCutShortIsNamed) {
    const std::string dir = tempDir("scan_dicom_cut_large");
    for (int k = 0; k < 3; ++k)
        writeDicomSlice(dir + "/s" + std::to_string(k) + ".dcm", {.position = kFirst + double(k) * kNormal, .rows = 64, .columns = 64}, k);
    const std::string bytes = readBytes(dir + "/s1.dcm");
    writeBytes(dir + "/s1.dcm", bytes.substr(0, bytes.size() - 1000));
    EXPECT_EQ(inputErrorOf([&] { gridOf(dir); }), dir + "/s1.dcm: damaged or truncated DICOM file");
}

// ---- the command, and bad input

TEST(ScanImport, CommandWritesTheGridWithItsMetadata) {
    const std::string dir = writeSeries("scan_cli");
    const std::string out = tempDir("scan_cli_out") + "/ct.vdb";
    const CliResult r = runCli("import " + dir + " -o " + out + " --background -1000");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("DICOM CT, 4 x 5 x 6 voxels of 0.5 x 0.75 x 1.25, values -1712 .. 1976 HU"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("skipped 1 file that is not a DICOM slice: README.txt"), std::string::npos) << r.out;
    initOpenVdb();
    openvdb::io::File file(out);
    file.open();
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    EXPECT_EQ(grid->metaValue<std::string>("scan_modality"), "CT");
    EXPECT_EQ(grid->metaValue<std::string>("scan_units"), "HU");
    EXPECT_EQ(grid->metaValue<float>("scan_value_min"), -1712.0f);
    EXPECT_EQ(grid->metaValue<float>("scan_background"), -1000.0f);
    EXPECT_EQ(grid->background(), -1000.0f);
}

// Each bad input: exit 2, one line naming the file and the problem, and no output file.
void expectRefused(const std::string& args, const std::string& out, const std::string& message) {
    const CliResult r = runCli("import " + args + " -o " + out);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err, "voxlux: error: " + message + "\n") << args;
    EXPECT_FALSE(fs::exists(out)) << args;
    for (const auto& entry : fs::directory_iterator(fs::path(out).parent_path()))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left behind: " << entry.path();
}

TEST(ScanImport, BadInputIsRefusedInOneLineLeavingNothing) {
    const std::string dir = tempDir("scan_bad");
    const std::string out = tempDir("scan_bad_out") + "/out.vdb";
    writeBytes(dir + "/short.raw", std::string(100, '\0'));
    expectRefused(dir + "/short.raw --dims 4,4,4 --type u16", out,
                  dir + "/short.raw: truncated: 4x4x4 u16 voxels after 0 header bytes need 128 bytes, the file has 100");
    expectRefused(dir + "/short.raw --dims 3,3,3 --type u8", out,
                  dir + "/short.raw: larger than its layout: 3x3x3 u8 voxels after 0 header bytes need 27 bytes, the file has 100");
    expectRefused(dir + "/short.raw --dims 5,5,4 --type u32", out,
                  dir + "/short.raw: --type 'u32' is not a voxel type voxlux imports (u8, u16, i16 or f32)");
    expectRefused(dir + "/short.raw --type u8", out,
                  dir + "/short.raw: --type, --spacing, --header-bytes and --endian describe a raw file, and need --dims X,Y,Z");
    expectRefused(dir + "/short.raw", out,
                  dir + "/short.raw: not a scan voxlux recognises (a DICOM folder, NIfTI .nii, VolPack .den); for raw voxels give "
                        "--dims X,Y,Z and --type");
    expectRefused(dir + "/absent.nii", out, dir + "/absent.nii: no such file or folder");

    writeNifti(dir + "/whole.nii", {1, Orientation::Sform, false});
    const std::string whole = readBytes(dir + "/whole.nii");
    writeBytes(dir + "/cut.nii", whole.substr(0, whole.size() - 30));
    expectRefused(dir + "/cut.nii", out,
                  dir + "/cut.nii: truncated: its 7x6x5 voxels need " + std::to_string(whole.size()) + " bytes, the file has " +
                      std::to_string(whole.size() - 30));
    writeBytes(dir + "/header.nii", whole.substr(0, 200));
    expectRefused(dir + "/header.nii", out, dir + "/header.nii: not a readable NIfTI file (its header is missing or damaged)");

    const std::string empty = tempDir("scan_bad_empty_folder");
    expectRefused(empty, out, empty + ": holds no DICOM images");
    const std::string series = writeSeries("scan_bad_cut_series");
    const std::string slice = readBytes(series + "/IM2.dcm");
    writeBytes(series + "/IM2.dcm", slice.substr(0, slice.size() - 10));
    expectRefused(series, out, series + "/IM2.dcm: damaged or truncated DICOM file");
}

}  // namespace
}  // namespace voxlux::test
