#include "scan/scan_import.h"

#include <cmath>
#include <filesystem>
#include <limits>

#include "core/error.h"
#include "core/progress.h"
#include "io/exr_writer.h"
#include "scan/dicom_reader.h"
#include "scan/nifti_reader.h"
#include "volume/up_axis.h"
#include "volume/vdb_loader.h"

namespace voxlux {

std::unique_ptr<ScanReader> openScan(const std::string& input, const ImportOptions& options,
                                     std::vector<std::string>& skipped_files) {
    if (std::filesystem::is_directory(input)) {
        DicomSkipped skipped;
        auto reader = openDicomSeries(input, skipped);
        skipped_files = skipped.files;
        return reader;
    }
    if (!std::filesystem::exists(input)) throw InputError(input + ": no such file or folder");
    if (!std::filesystem::is_regular_file(input)) throw InputError(input + ": not a file or a folder (a device or a pipe)");
    if (options.raw) return openRaw(input, *options.raw, "raw");
    if (isNiftiName(input)) return openNifti(input);
    if (auto den = denLayout(input)) return openRaw(input, *den, "VolPack .den");
    throw InputError(input + ": not a scan voxlux recognises (a DICOM folder, NIfTI .nii, VolPack .den); "
                     "for raw voxels give --dims X,Y,Z and --type");
}

openvdb::FloatGrid::Ptr buildScanGrid(ScanReader& reader, const ImportOptions& options, ImportReport& report) {
    const ScanInfo& info = reader.info();
    report.info = info;
    const glm::ivec3 d = info.dims;
    report.voxels = std::uint64_t(d.x) * std::uint64_t(d.y) * std::uint64_t(d.z);
    std::vector<float> slice(size_t(d.x) * size_t(d.y));

    // Pass 1: the value range, which gives the default background and the metadata.
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (int k = 0; k < d.z; ++k) {
        throwIfInterrupted();
        reader.readSlice(k, slice.data());
        for (float v : slice)
            if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
            else ++report.non_finite;
    }
    if (!(lo <= hi)) lo = hi = 0.0f;   // no finite voxel: an empty grid
    report.min_value = lo;
    report.max_value = hi;
    report.background = options.background.value_or(lo);

    // The matrix is the file's; OpenVDB's maps take row vectors (p * M), glm's column vectors.
    openvdb::math::Mat4d m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c) = info.index_to_world[r][c];
    if (std::abs(m.getMat3().det()) < 1e-12 || !std::isfinite(m.getMat3().det()))
        throw InputError(info.source + ": its voxel-to-world matrix is singular; the file's orientation is damaged");

    // Pass 2: activate the voxels above the background.
    auto grid = openvdb::FloatGrid::create(report.background);
    grid->setName(options.grid_name);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
    auto acc = grid->getAccessor();
    for (int k = 0; k < d.z; ++k) {
        throwIfInterrupted();
        reader.readSlice(k, slice.data());
        for (int j = 0; j < d.y; ++j)
            for (int i = 0; i < d.x; ++i) {
                const float v = slice[size_t(j) * size_t(d.x) + size_t(i)];
                if (std::isfinite(v) && v > report.background) acc.setValueOn(openvdb::Coord(i, j, k), v);
            }
    }
    grid->pruneGrid();
    report.active_voxels = grid->activeVoxelCount();

    grid->insertMeta("scan_format", openvdb::StringMetadata(info.format));
    grid->insertMeta("scan_modality", openvdb::StringMetadata(info.modality));
    grid->insertMeta("scan_units", openvdb::StringMetadata(info.units));
    grid->insertMeta("scan_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(d.x, d.y, d.z)));
    grid->insertMeta("scan_value_min", openvdb::FloatMetadata(lo));
    grid->insertMeta("scan_value_max", openvdb::FloatMetadata(hi));
    grid->insertMeta("scan_background", openvdb::FloatMetadata(report.background));
    // Which way is up and which side is the face, for the quick form's camera (up_axis.h).
    const std::string up = options.up.value_or(info.up), front = options.front.value_or(info.front);
    if (!up.empty()) {
        grid->insertMeta("up_axis", openvdb::StringMetadata(up));
        grid->insertMeta("front_axis", openvdb::StringMetadata(front));
    }
    return grid;
}

ImportReport importScan(const std::string& input, const std::string& output, const ImportOptions& options) {
    initOpenVdb();
    if (options.up.has_value() != options.front.has_value())
        throw InputError(input + ": --up and --front go together: the axis toward the head and the one toward the face");
    if (options.up) {
        const auto up = parseSignedAxis(*options.up), front = parseSignedAxis(*options.front);
        if (!up || !front) throw InputError(input + ": --up and --front are axes: x, y, z, -x, -y or -z");
        if (glm::dot(*up, *front) != 0.0f) throw InputError(input + ": --up " + *options.up + " and --front " + *options.front + " must be different axes");
    }
    checkWritable(output);
    ImportReport report;
    auto reader = openScan(input, options, report.skipped_files);
    auto grid = buildScanGrid(*reader, options, report);
    grid->insertMeta("scan_source", openvdb::StringMetadata(std::filesystem::path(input).filename().string()));
    writeAtomically(output, [&](const std::string& tmp) { openvdb::io::File(tmp).write({grid}); });
    return report;
}

}  // namespace voxlux
