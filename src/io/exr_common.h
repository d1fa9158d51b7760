// What voxlux's flat and deep EXR writers share: the header with the render's metadata, the
// compression names, and the values a file may hold.
#pragma once
#include <string>

#include <ImfCompression.h>
#include <ImfHeader.h>

#include "io/exr_writer.h"

namespace voxlux {

// A header of width x height with voxlux's metadata (docs/scene.md, Output metadata): version,
// scene hash, frame, stage seconds, camera matrices, colour space, config, exposure, chromaticities.
Imf::Header voxluxExrHeader(int width, int height, const ExrMetadata& meta);

// One of knownCompressions(); throws std::invalid_argument for another name.
Imf::Compression exrCompression(const std::string& name);

// `v` as a file holds it: NaN and Inf as 0, counted; past the half range (when `half`) saturated
// at 65504, counted. No NaN or Inf reaches a file.
float exrStorable(float v, bool half, ExrWriteReport& report);

}  // namespace voxlux
