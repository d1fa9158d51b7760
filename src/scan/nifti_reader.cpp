#include "scan/nifti_reader.h"

#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include <nifti2_io.h>

#include "core/error.h"

namespace voxlux {
namespace {

struct NiftiFree {
    void operator()(nifti_image* nim) const { nifti_image_free(nim); }
};
using NiftiPtr = std::unique_ptr<nifti_image, NiftiFree>;

bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

template <typename T>
void convertSlice(const void* data, size_t first, size_t n, double slope, double inter, float* out) {
    const T* p = static_cast<const T*>(data) + first;
    for (size_t i = 0; i < n; ++i) out[i] = float(double(p[i]) * slope + inter);
}

class NiftiReader : public ScanReader {
public:
    NiftiReader(const std::string& file, NiftiPtr nim, int version) : nim_(std::move(nim)) {
        const nifti_image& n = *nim_;
        info_.source = file;
        info_.dims = glm::ivec3(int(n.nx), int(n.ny), int(n.nz));
        info_.format = version == 2 ? "NIfTI-2" : n.nifti_type == NIFTI_FTYPE_ANALYZE ? "ANALYZE 7.5" : "NIfTI-1";
        const nifti_dmat44* m = n.sform_code > 0 ? &n.sto_xyz : n.qform_code > 0 ? &n.qto_xyz : nullptr;
        if (m) {   // RAS: superior +z, anterior +y
            info_.up = "z";
            info_.front = "y";
            for (int row = 0; row < 4; ++row)
                for (int col = 0; col < 4; ++col) info_.index_to_world[col][row] = m->m[row][col];
        } else {
            const double pixdim[3] = {n.dx, n.dy, n.dz};
            for (int a = 0; a < 3; ++a) info_.index_to_world[a][a] = pixdim[a] > 0.0 ? pixdim[a] : 1.0;
        }
        const bool scaled = n.scl_slope != 0.0 && std::isfinite(n.scl_slope) && std::isfinite(n.scl_inter);
        slope_ = scaled ? n.scl_slope : 1.0;
        inter_ = scaled ? n.scl_inter : 0.0;
    }

    void readSlice(int k, float* out) override {
        const size_t n = size_t(info_.dims.x) * size_t(info_.dims.y), first = n * size_t(k);
        const void* d = nim_->data;
        switch (nim_->datatype) {
            case DT_UINT8: convertSlice<std::uint8_t>(d, first, n, slope_, inter_, out); break;
            case DT_INT8: convertSlice<std::int8_t>(d, first, n, slope_, inter_, out); break;
            case DT_INT16: convertSlice<std::int16_t>(d, first, n, slope_, inter_, out); break;
            case DT_UINT16: convertSlice<std::uint16_t>(d, first, n, slope_, inter_, out); break;
            case DT_INT32: convertSlice<std::int32_t>(d, first, n, slope_, inter_, out); break;
            case DT_UINT32: convertSlice<std::uint32_t>(d, first, n, slope_, inter_, out); break;
            case DT_FLOAT32: convertSlice<float>(d, first, n, slope_, inter_, out); break;
            case DT_FLOAT64: convertSlice<double>(d, first, n, slope_, inter_, out); break;
        }
    }

private:
    NiftiPtr nim_;
    double slope_ = 1.0, inter_ = 0.0;
};

bool supportedType(int datatype) {
    for (int t : {DT_UINT8, DT_INT8, DT_INT16, DT_UINT16, DT_INT32, DT_UINT32, DT_FLOAT32, DT_FLOAT64})
        if (datatype == t) return true;
    return false;
}

}  // namespace

bool isNiftiName(const std::string& file) {
    for (const char* ext : {".nii", ".nii.gz", ".hdr", ".img", ".hdr.gz", ".img.gz"})
        if (endsWith(file, ext)) return true;
    return false;
}

std::unique_ptr<ScanReader> openNifti(const std::string& file) {
    nifti_set_debug_level(0);   // the library prints its complaints; ours are one line
    // The version is the header's: libnifti's image keeps the type its names suggest.
    int version = 0;
    std::free(nifti_read_header(file.c_str(), &version, 1));
    NiftiPtr nim(nifti_image_read(file.c_str(), 0));
    if (!nim) throw InputError(file + ": not a readable NIfTI file (its header is missing or damaged)");
    const nifti_image& n = *nim;
    if (n.nx < 1 || n.ny < 1 || n.nz < 1 || n.nx > INT32_MAX / 2 || n.ny > INT32_MAX / 2 || n.nz > INT32_MAX / 2)
        throw InputError(file + ": damaged: dimensions " + std::to_string(n.nx) + "x" + std::to_string(n.ny) + "x" +
                         std::to_string(n.nz));
    if (double(n.nx) * double(n.ny) * double(n.nz) > kMaxScanVoxels)
        throw InputError(file + ": damaged or too large: dimensions " + std::to_string(n.nx) + "x" + std::to_string(n.ny) + "x" +
                         std::to_string(n.nz) + " are more than the 2^34 voxels voxlux imports");
    const int64_t volumes = n.nvox / (n.nx * n.ny * n.nz);
    if (volumes > 1)
        throw InputError(file + ": holds " + std::to_string(volumes) +
                         " volumes (a time series or vectors); voxlux imports a 3-D volume, so extract one first");
    if (!supportedType(n.datatype))
        throw InputError(file + ": voxels of type " + nifti_datatype_string(n.datatype) +
                         " are not a scalar voxlux imports (uint8, int8, int16, uint16, int32, uint32, float32, float64)");
    // An uncompressed file must hold every voxel; libnifti would read a short one into a zeroed
    // buffer without a word, so check its size first.
    if (n.iname && !endsWith(n.iname, ".gz")) {
        const std::uint64_t need = std::uint64_t(n.iname_offset) + std::uint64_t(n.nvox) * std::uint64_t(n.nbyper);
        const std::uint64_t have = std::filesystem::exists(n.iname) ? std::filesystem::file_size(n.iname) : 0;
        if (have < need)
            throw InputError(std::string(n.iname) + ": truncated: its " + std::to_string(n.nx) + "x" + std::to_string(n.ny) +
                             "x" + std::to_string(n.nz) + " voxels need " + std::to_string(need) + " bytes, the file has " +
                             std::to_string(have));
    }
    if (nifti_image_load(nim.get()) != 0 || !nim->data)
        throw InputError(file + ": cannot read its voxels (truncated or damaged)");
    return std::make_unique<NiftiReader>(file, std::move(nim), version);
}

}  // namespace voxlux
