// `voxlux import`: a scan (DICOM series, NIfTI, raw or VolPack .den) to a sparse float VDB grid.
// Two streaming passes over the slices: the first finds the value range, the second activates
// the voxels above the background, so memory follows the tissue, not the scanner's box (one
// slice of floats beside the grid, and what the reader holds: NIfTI's library loads a file whole). The grid's transform puts every voxel where the file does,
// oblique orientations included; the source (format, modality, units, value range, background)
// goes into the grid's metadata. The .vdb is written to a temporary file and renamed.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "scan/raw_reader.h"
#include "scan/scan_reader.h"

namespace voxlux {

struct ImportOptions {
    std::string grid_name = "density";
    std::optional<float> background;   // voxels at or below it are inactive; default: the scan's minimum
    std::optional<RawLayout> raw;      // the layout of a raw file (--dims, --type, ...)
    // --up and --front: the world axes toward the head and the face ("x", "-y", ...), for a file
    // that does not say (raw, .den) or says wrong; both or neither.
    std::optional<std::string> up, front;
};

struct ImportReport {
    ScanInfo info;
    float min_value = 0.0f, max_value = 0.0f;   // over the finite voxels
    float background = 0.0f;
    std::uint64_t voxels = 0;                   // dims.x * dims.y * dims.z
    std::uint64_t active_voxels = 0;
    std::uint64_t non_finite = 0;               // NaN or infinite voxels, left inactive
    std::vector<std::string> skipped_files;     // of a DICOM folder: files that are not DICOM images
};

// The reader for `input`: a folder is a DICOM series; a raw layout, a raw file; a NIfTI name,
// NIfTI; a file with a VolPack header, .den. Throws InputError for anything else.
std::unique_ptr<ScanReader> openScan(const std::string& input, const ImportOptions& options,
                                     std::vector<std::string>& skipped_files);

// The sparse grid of a scan, named options.grid_name, with the scan's transform and metadata.
openvdb::FloatGrid::Ptr buildScanGrid(ScanReader& reader, const ImportOptions& options, ImportReport& report);

// Opens `input`, builds its grid and writes it to `output` whole or not at all.
ImportReport importScan(const std::string& input, const std::string& output, const ImportOptions& options);

}  // namespace voxlux
