// A scanned volume (CT, MRI) as a stack of slices: its size, where each voxel sits in the world,
// and its values slice by slice, so that an import holds one slice of floats at a time beside the
// grid it builds (a reader may hold the file's own voxels: NIfTI's library loads them whole). Values are what the file means them to be (its rescale applied: Hounsfield units for CT).
// Each format is one reader: raw_reader.h (raw and VolPack .den), nifti_reader.h, dicom_reader.h.
#pragma once
#include <memory>
#include <string>

#include <glm/glm.hpp>

namespace voxlux {

// The most voxels a scan may have (2^34, 17 G: 64 GB of floats in one slice stack); a header that
// claims more is damaged, or a mistaken raw layout.
constexpr double kMaxScanVoxels = 17179869184.0;

struct ScanInfo {
    std::string source;                // the file or folder, for messages
    glm::ivec3 dims{0};                // voxels along i (fastest), j, k (slices)
    glm::dmat4 index_to_world{1.0};    // voxel (i, j, k)'s centre -> world; RAS millimetres for NIfTI and DICOM
    std::string format;                // "raw", "VolPack .den", "NIfTI-1", "NIfTI-2", "DICOM"
    std::string modality;              // "CT", "MR", ...; "" when the file does not say
    std::string units;                 // "HU" for CT; "" when the file does not say
    // The world axes toward the head and the face ("z" and "y" in RAS), as up_axis.h's metadata
    // spells them; "" when the file does not say (raw, .den, NIfTI without an orientation).
    std::string up, front;
};

class ScanReader {
public:
    virtual ~ScanReader() = default;
    const ScanInfo& info() const { return info_; }
    // Slice k (0 <= k < dims.z): dims.x * dims.y values, i fastest. Throws InputError naming the
    // file when it cannot be read. May be called more than once for a slice.
    virtual void readSlice(int k, float* out) = 0;

protected:
    ScanInfo info_;
};

}  // namespace voxlux
