// Named two-dimensional transfer functions for common scans, a starting point to edit: CT in
// Hounsfield units (the same numbers fit every calibrated CT scanner), and a T1 MRI head whose
// numbers fit 8-bit data scaled as the bundled head (MRI has no absolute units: another scanner's
// values need the regions moved). Gradients are in value units per millimetre. docs/scans.md
// lists every region's numbers.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace voxlux {

struct TransferPreset {
    std::string name;
    std::string description;
    std::vector<TransferRegion> regions;
};

const std::vector<TransferPreset>& transferPresets();

// The preset called `name`, or null.
const TransferPreset* findTransferPreset(const std::string& name);

}  // namespace voxlux
