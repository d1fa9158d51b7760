// Deep scanline OpenEXR: each pixel's deep samples (shaders/vx_deep.h) as the channels Nuke's
// DeepRead and OpenEXR's CompositeDeepScanLine read: R, G, B, A (premultiplied, the output's
// pixel type) and Z, ZBack (float, camera-space depth), with the flat image's metadata. Written
// to a temporary file and renamed, as every output. Cost: about 24 bytes a sample before
// compression; deep scanline files allow only none, rle and zips, so the other compressions are
// written as zips.
#pragma once
#include <string>

#include "io/exr_writer.h"

namespace voxlux {

// Throws InputError "<path>: ..." when the file cannot be written; nothing is left at `path` then.
ExrWriteReport writeDeepExr(const std::string& path, const RenderImage& image, const OutputSpec& spec, const ExrMetadata& meta);

}  // namespace voxlux
