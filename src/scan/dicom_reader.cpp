#include "scan/dicom_reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>
#include <dcmtk/oflog/oflog.h>

#include "core/error.h"

namespace voxlux {
namespace {

namespace fs = std::filesystem;

// A Part 10 file: 128 bytes of preamble, then "DICM".
bool hasDicomMagic(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    char magic[4] = {};
    return in.seekg(128) && in.read(magic, 4) && std::memcmp(magic, "DICM", 4) == 0;
}

std::string text(DcmDataset& ds, const DcmTagKey& tag) {
    OFString s;
    return ds.findAndGetOFString(tag, s).good() ? std::string(s.c_str()) : std::string();
}

// `count` numbers of a multi-valued tag, or throws naming the file and the tag.
std::vector<double> numbers(DcmDataset& ds, const DcmTagKey& tag, int count, const std::string& file, const char* name) {
    std::vector<double> out(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) {
        Float64 v = 0;
        if (ds.findAndGetFloat64(tag, v, unsigned(i)).bad() || !std::isfinite(v))
            throw InputError(file + ": has no " + name + " (" + std::to_string(count) + " numbers); voxlux needs it to place the slice");
        out[size_t(i)] = v;
    }
    return out;
}

double numberOr(DcmDataset& ds, const DcmTagKey& tag, double fallback) {
    Float64 v = 0;
    return ds.findAndGetFloat64(tag, v).good() && std::isfinite(v) ? v : fallback;
}

// One slice's header: what places it and what its pixels are.
struct Slice {
    std::string file;
    std::string series, description, modality;
    int rows = 0, columns = 0;
    glm::dvec3 position{0.0}, row_dir{0.0}, column_dir{0.0};
    glm::dvec2 spacing{0.0};            // between rows, between columns (PixelSpacing's order)
    int bits_allocated = 0, bits_stored = 0, high_bit = 0, signed_pixels = 0, samples = 1, frames = 1;
    double slope = 1.0, intercept = 0.0;
    double thickness = 1.0;             // SliceThickness: a single slice's third edge
    bool encapsulated = false;
    std::string transfer_syntax;
};

// The slice a file holds, or nothing for a DICOM file that is not a slice of a volume (a
// DICOMDIR, a structured report, a dose report's screenshot: no pixels or no position).
std::optional<Slice> readHeader(const fs::path& path) {
    DcmFileFormat ff;
    const std::string file = path.string();
    // Elements longer than 4 KB (the pixels) stay on disk.
    if (ff.loadFile(file.c_str(), EXS_Unknown, EGL_noChange, 4096).bad()) throw InputError(file + ": damaged or truncated DICOM file");
    DcmDataset& ds = *ff.getDataset();
    if (!ds.tagExists(DCM_PixelData) || !ds.tagExists(DCM_ImagePositionPatient)) return std::nullopt;
    Slice s;
    s.file = file;
    s.series = text(ds, DCM_SeriesInstanceUID);
    s.description = text(ds, DCM_SeriesDescription);
    s.modality = text(ds, DCM_Modality);
    Uint16 u = 0;
    s.rows = ds.findAndGetUint16(DCM_Rows, u).good() ? u : 0;
    s.columns = ds.findAndGetUint16(DCM_Columns, u).good() ? u : 0;
    s.bits_allocated = ds.findAndGetUint16(DCM_BitsAllocated, u).good() ? u : 0;
    s.bits_stored = ds.findAndGetUint16(DCM_BitsStored, u).good() ? u : s.bits_allocated;
    s.high_bit = ds.findAndGetUint16(DCM_HighBit, u).good() ? u : s.bits_stored - 1;
    s.signed_pixels = ds.findAndGetUint16(DCM_PixelRepresentation, u).good() ? u : 0;
    s.samples = ds.findAndGetUint16(DCM_SamplesPerPixel, u).good() ? u : 1;
    Sint32 frames = 1;
    s.frames = ds.findAndGetSint32(DCM_NumberOfFrames, frames).good() ? int(frames) : 1;
    const auto position = numbers(ds, DCM_ImagePositionPatient, 3, file, "ImagePositionPatient");
    const auto orientation = numbers(ds, DCM_ImageOrientationPatient, 6, file, "ImageOrientationPatient");
    const auto spacing = numbers(ds, DCM_PixelSpacing, 2, file, "PixelSpacing");
    s.position = {position[0], position[1], position[2]};
    s.row_dir = {orientation[0], orientation[1], orientation[2]};
    s.column_dir = {orientation[3], orientation[4], orientation[5]};
    s.spacing = {spacing[0], spacing[1]};
    s.slope = numberOr(ds, DCM_RescaleSlope, 1.0);
    s.intercept = numberOr(ds, DCM_RescaleIntercept, 0.0);
    s.thickness = numberOr(ds, DCM_SliceThickness, 1.0);
    const DcmXfer xfer(ds.getOriginalXfer());
    s.encapsulated = xfer.isEncapsulated();
    s.transfer_syntax = xfer.getXferName();
    return s;
}

void checkPixels(const Slice& s) {
    if (s.rows < 1 || s.columns < 1) throw InputError(s.file + ": has no Rows or Columns");
    if (s.samples != 1) throw InputError(s.file + ": has " + std::to_string(s.samples) + " samples a pixel (colour); voxlux imports greyscale scans");
    if (s.frames != 1)
        throw InputError(s.file + ": holds " + std::to_string(s.frames) + " frames (an enhanced multi-frame image); voxlux imports one slice a file");
    if (s.bits_allocated != 8 && s.bits_allocated != 16)
        throw InputError(s.file + ": " + std::to_string(s.bits_allocated) + " bits a pixel; voxlux imports 8 or 16");
    if (s.bits_stored < 1 || s.high_bit < s.bits_stored - 1 || s.high_bit >= s.bits_allocated)
        throw InputError(s.file + ": damaged: BitsStored " + std::to_string(s.bits_stored) + " and HighBit " + std::to_string(s.high_bit) +
                         " do not fit in BitsAllocated " + std::to_string(s.bits_allocated));
    if (s.encapsulated)
        throw InputError(s.file + ": its pixels are compressed (" + s.transfer_syntax +
                         "); decompress the series first, e.g. with dcmdjpeg");
    if (!(s.spacing.x > 0.0 && s.spacing.y > 0.0)) throw InputError(s.file + ": PixelSpacing must be positive");
    const double r = glm::length(s.row_dir), c = glm::length(s.column_dir);
    if (std::abs(r - 1.0) > 1e-3 || std::abs(c - 1.0) > 1e-3 || std::abs(glm::dot(s.row_dir, s.column_dir)) > 1e-3)
        throw InputError(s.file + ": ImageOrientationPatient is not two perpendicular unit vectors");
}

bool sameGeometry(const Slice& a, const Slice& b) {
    return a.rows == b.rows && a.columns == b.columns && a.bits_allocated == b.bits_allocated &&
           glm::length(a.row_dir - b.row_dir) < 1e-4 && glm::length(a.column_dir - b.column_dir) < 1e-4 &&
           glm::length(a.spacing - b.spacing) < 1e-4 * glm::length(a.spacing);
}

std::string mm(double v) {
    std::ostringstream s;
    s.precision(4);
    s << v << " mm";
    return s.str();
}

class DicomReader : public ScanReader {
public:
    explicit DicomReader(std::vector<Slice> slices) : slices_(std::move(slices)) {}
    ScanInfo& mutableInfo() { return info_; }

    void readSlice(int k, float* out) override {
        const Slice& s = slices_[size_t(k)];
        DcmFileFormat ff;
        if (ff.loadFile(s.file.c_str()).bad()) throw InputError(s.file + ": damaged or truncated DICOM file");
        DcmDataset& ds = *ff.getDataset();
        const size_t n = size_t(s.rows) * size_t(s.columns);
        // The stored bits end at HighBit: moved to the top of an int and back, they are sign-extended.
        const int up = 31 - s.high_bit, down = 32 - s.bits_stored;
        const auto value = [&](unsigned raw) {
            const int v = s.signed_pixels ? int(raw << up) >> down : int((raw << up) >> down);
            return float(double(v) * s.slope + s.intercept);
        };
        unsigned long count = 0;
        if (s.bits_allocated == 8) {
            const Uint8* p = nullptr;
            if (ds.findAndGetUint8Array(DCM_PixelData, p, &count).bad() || !p || count < n)
                throw InputError(s.file + ": truncated: its pixel data holds " + std::to_string(count) + " of " + std::to_string(n) + " pixels");
            for (size_t i = 0; i < n; ++i) out[i] = value(p[i]);
        } else {
            const Uint16* p = nullptr;
            if (ds.findAndGetUint16Array(DCM_PixelData, p, &count).bad() || !p || count < n)
                throw InputError(s.file + ": truncated: its pixel data holds " + std::to_string(count) + " of " + std::to_string(n) + " pixels");
            for (size_t i = 0; i < n; ++i) out[i] = value(p[i]);
        }
    }

private:
    std::vector<Slice> slices_;
};

}  // namespace

std::unique_ptr<ScanReader> openDicomSeries(const std::string& folder, DicomSkipped& skipped) {
    if (!fs::is_directory(folder)) throw InputError(folder + ": not a folder (a DICOM series is a folder of slices)");
    OFLog::configure(OFLogger::FATAL_LOG_LEVEL);   // DCMTK's own warnings; problems are reported here, one line each
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(folder))
        if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());

    std::map<std::string, std::vector<Slice>> series;
    for (const fs::path& f : files) {
        if (!hasDicomMagic(f)) {
            skipped.files.push_back(f.filename().string());
            continue;
        }
        std::optional<Slice> s = readHeader(f);
        if (s) series[s->series].push_back(std::move(*s));
        else skipped.files.push_back(f.filename().string());
    }
    if (series.empty()) throw InputError(folder + ": holds no DICOM images");
    if (series.size() > 1) {
        std::string list;
        for (const auto& [uid, slices] : series)
            list += (list.empty() ? "" : ", ") + (uid.empty() ? std::string("(no SeriesInstanceUID)") : uid) + " (" +
                    slices.front().modality + (slices.front().description.empty() ? "" : " '" + slices.front().description + "'") +
                    ", " + std::to_string(slices.size()) + " files)";
        throw InputError(folder + ": holds " + std::to_string(series.size()) + " series: " + list +
                         "; put each series in a folder of its own");
    }

    std::vector<Slice> slices = std::move(series.begin()->second);
    for (const Slice& s : slices) {
        checkPixels(s);
        if (!sameGeometry(s, slices.front()))
            throw InputError(s.file + ": its size, pixel spacing or orientation differs from " + slices.front().file + "'s");
    }
    const glm::dvec3 normal = glm::cross(slices.front().row_dir, slices.front().column_dir);
    const auto along = [&](const Slice& s) { return glm::dot(s.position, normal); };
    std::sort(slices.begin(), slices.end(), [&](const Slice& a, const Slice& b) { return along(a) < along(b); });
    for (size_t k = 1; k < slices.size(); ++k)
        if (along(slices[k]) - along(slices[k - 1]) < 1e-4)
            throw InputError(folder + ": " + fs::path(slices[k - 1].file).filename().string() + " and " +
                             fs::path(slices[k].file).filename().string() + " are at the same position");
    const Slice& first = slices.front();
    glm::dvec3 step = normal * (first.thickness > 0.0 ? first.thickness : 1.0);
    if (slices.size() > 1) {
        step = (slices.back().position - first.position) / double(slices.size() - 1);
        bool even = true;
        for (size_t k = 1; k < slices.size(); ++k)
            even = even && glm::length(slices[k].position - (first.position + double(k) * step)) <= 0.01 * glm::length(step);
        if (!even) {   // name the gap furthest from the median one
            std::vector<double> gaps;
            for (size_t k = 1; k < slices.size(); ++k) gaps.push_back(along(slices[k]) - along(slices[k - 1]));
            std::vector<double> sorted = gaps;
            std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
            const double median = sorted[sorted.size() / 2];
            const size_t worst = size_t(std::max_element(gaps.begin(), gaps.end(), [&](double a, double b) {
                                            return std::abs(a - median) < std::abs(b - median);
                                        }) - gaps.begin());
            throw InputError(folder + ": the slice spacing is irregular: " + mm(gaps[worst]) + " between " +
                             fs::path(slices[worst].file).filename().string() + " and " +
                             fs::path(slices[worst + 1].file).filename().string() + ", where the median gap is " + mm(median) +
                             "; voxlux needs evenly spaced slices (resample the series, or import its parts)");
        }
    }

    auto reader = std::make_unique<DicomReader>(slices);
    ScanInfo& info = reader->mutableInfo();
    info.source = folder;
    info.dims = {first.columns, first.rows, int(slices.size())};
    info.format = "DICOM";
    info.modality = first.modality;
    info.units = first.modality == "CT" ? "HU" : "";
    info.up = "z";   // RAS, as below: superior +z, anterior +y
    info.front = "y";
    // Voxel (i, j, k): column i, row j of slice k. LPS -> RAS negates x and y.
    const glm::dmat4 lps(glm::dvec4(first.row_dir * first.spacing.y, 0.0), glm::dvec4(first.column_dir * first.spacing.x, 0.0),
                         glm::dvec4(step, 0.0), glm::dvec4(first.position, 1.0));
    info.index_to_world = glm::dmat4(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, -1, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, 0, 0, 1)) * lps;
    return reader;
}

}  // namespace voxlux
