// How a grid is reconstructed between its samples: trilinear, or the smoother cubic B-spline
// (shaders/vx_sample.h), which hides the voxel staircase of a low-resolution cache. The render's
// grids and a lighting method's volume each pick one.
#pragma once

namespace voxlux {

enum class Filter { Trilinear, Tricubic };

}  // namespace voxlux
