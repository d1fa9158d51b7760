// The material's 1D transfer function (scanned data) as the kernel sees it: a table of
// VX_TF_LUT_SIZE entries (rgb albedo tint, a extinction multiplier) over the control points' range.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxlux {

// Samples the piecewise-linear control points evenly; without points, a constant row of 1.
std::vector<glm::vec4> bakeTransfer(const std::vector<TransferPoint>& points);

// Largest extinction multiplier the kernel can produce for raw values in [lo, hi]: the largest
// table entry the kernel may interpolate from for that range (the kernel interpolates linearly).
float maxTransferExtinction(const std::vector<glm::vec4>& table, const std::vector<TransferPoint>& points, float lo,
                            float hi);

}  // namespace voxlux
