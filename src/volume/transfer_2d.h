// The two-dimensional transfer function applied to a loaded volume's grid: each voxel's value and
// gradient magnitude (central differences in world units, through the grid's affine map, so that
// anisotropic and oblique scans measure gradients alike) become an extinction grid and an albedo
// grid, which the bricks, the lighting and the march then read as any density and colour grid,
// and, when the regions carry them, a transport-colour grid the indirect light's sweeps read and a
// surface-weight grid the march reads.
// Voxels are classified before they are interpolated, as Levoy (1988) and VolPack classify.
// Cost: one pass over the active voxels and their face neighbours (six reads each); the output
// holds only the voxels some region selects.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"
#include "volume/vdb_loader.h"

namespace voxlux {

// `raw` with its density replaced by the regions' extinction, its colour by their albedo, and its
// transport colour and surface weight set when every region has them.
// Voxels whose value or gradient is not finite are transparent and counted in `warnings`.
LoadedVolume applyTransfer2d(const LoadedVolume& raw, const std::vector<TransferRegion>& regions, std::vector<std::string>& warnings);

}  // namespace voxlux
