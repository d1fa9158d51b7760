// Velocity grids for motion blur (render.motion_blur): the grid on the density's voxel centres,
// and how far the blurred medium reaches, which sets the bricks the atlas adds around the medium.
// Cost: one pass over the velocity grid's active voxels (centring a staggered grid, the top speed).
#pragma once
#include <optional>
#include <string>

#include <openvdb/openvdb.h>

#include "scene/scene.h"

namespace voxlux {

struct LoadedVolume;

// The grid names Houdini (vel, v) and Blender (velocity) give velocity, in the order they are tried.
const std::vector<std::string>& velocityGridNames();

// A staggered (MAC) grid, whose x component of voxel (i, j, k) lies on the face at i - 1/2 (as
// OpenVDB's staggered samplers read it), averaged onto the voxel centres; other grids as they are.
openvdb::Vec3SGrid::Ptr velocityAtVoxelCentres(openvdb::Vec3SGrid::Ptr grid);

// The largest length of the grid's active values (world units per second).
float maxSpeed(const openvdb::Vec3SGrid& grid);

// How many voxels the medium can move within the shutter at `max_speed` (world units per second)
// in a grid of voxel edge `voxel` (world units). Throws InputError naming `file` and `grid` past
// 256 voxels, which a mis-set velocity_scale gives.
float motionReachVoxels(float max_speed, float voxel, const MotionBlur& motion, const std::string& file, const std::string& grid);

// The velocity carried `voxels` voxels beyond its active voxels, one layer at a time, each new
// voxel the mean of its neighbours in the layers before. Simulators write velocity only where
// there is medium; the Eulerian lookup reads it at the points the medium moves to, which without
// this would see none and leave the leading edges unblurred. Cost: a pass over each new layer.
void extendVelocity(openvdb::Vec3SGrid& grid, int voxels);

// How many bricks of 8^3 voxels the medium can move within the shutter (0 without motion blur or
// velocity): motionReachVoxels over the loaded velocity.
int motionReachBricks(const LoadedVolume& volume, const std::optional<MotionBlur>& motion);

}  // namespace voxlux
