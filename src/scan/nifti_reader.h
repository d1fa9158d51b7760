// NIfTI-1 and NIfTI-2 volumes (.nii, .nii.gz, .hdr/.img pairs) through Debian's libnifti2, which
// reads both versions and both byte orders. A voxel's world position is the file's own: the sform
// when its code is set, else the qform, else the voxel size (pixdim) alone, as the NIfTI standard
// orders them; values get scl_slope and scl_inter. Holds the file's voxels in their own type.
#pragma once
#include <memory>
#include <string>

#include "scan/scan_reader.h"

namespace voxlux {

// Whether `file` has a NIfTI or ANALYZE name (.nii, .nii.gz, .hdr, .img).
bool isNiftiName(const std::string& file);

// `file` exists (openScan checks). Throws InputError naming the file: not NIfTI, truncated, 4-D, or a voxel type voxlux cannot use.
std::unique_ptr<ScanReader> openNifti(const std::string& file);

}  // namespace voxlux
