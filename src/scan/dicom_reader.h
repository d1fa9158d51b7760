// A DICOM series (one folder, one file per slice) through DCMTK. The slices are ordered by their
// ImagePositionPatient along the slice normal (the cross product of ImageOrientationPatient's row
// and column directions), whatever the files' names; the in-plane axes and PixelSpacing give the
// first two voxel edges, and the step between slice positions the third, so oblique and tilted
// stacks keep their geometry. World space is RAS millimetres, as NIfTI's: DICOM's patient space
// (LPS) with x and y negated. Values get RescaleSlope and RescaleIntercept (Hounsfield units for
// CT). Headers are read once; a slice's pixels are read when it is asked for.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "scan/scan_reader.h"

namespace voxlux {

// Files of the folder that were passed over (not DICOM, or DICOM that is not a slice: a DICOMDIR,
// a report, an image without ImagePositionPatient), for the import's report.
struct DicomSkipped {
    std::vector<std::string> files;
};

// Throws InputError naming the folder or a file: no images, mixed series (each named, with its
// description and number of files), slices of different sizes or orientations, irregular slice
// spacing, compressed pixel data, or a file that cannot be read.
std::unique_ptr<ScanReader> openDicomSeries(const std::string& folder, DicomSkipped& skipped);

}  // namespace voxlux
