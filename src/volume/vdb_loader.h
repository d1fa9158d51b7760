// Load stage: open a .vdb file and pick the grids a VolumeSpec names, with one-line errors for
// everything a pipeline throws at us (truncated files, wrong names, wrong types, level sets).
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <openvdb/openvdb.h>

#include "scene/scene.h"
#include "volume/up_axis.h"

namespace voxlux {

struct LoadedVolume {
    std::string file;
    openvdb::FloatGrid::ConstPtr density;
    std::vector<openvdb::FloatGrid::ConstPtr> emission;  // one per emission source, in its order
    openvdb::Vec3SGrid::ConstPtr color;      // null unless the spec names one
    openvdb::Vec3SGrid::ConstPtr transport;  // per-voxel transport colour (a 2D transfer function's
                                             // regions, Kniss Eq. 8); null: effects.indirect's colour
    openvdb::FloatGrid::ConstPtr surface;    // per-voxel surface weight (the regions', Kniss Eq. 11);
                                             // null: 1, the gradient's ramp alone
    openvdb::Vec3SGrid::ConstPtr velocity;   // render.motion_blur's, on the voxel centres; else null
    float max_speed = 0.0f;                  // the velocity's largest length (world units per second)
    glm::mat4 index_to_world{1.0f};          // affine, from the density grid
    UpAxisGuess up;                          // as the file says, from the density grid
    std::vector<std::string> warnings;
};

// One grid of a file as `voxlux info` lists it (metadata and tree statistics).
struct GridSummary {
    std::string name;
    std::string value_type;
    std::string grid_class;
    openvdb::Index64 active_voxels = 0;
    openvdb::Index64 active_tiles = 0;
    openvdb::CoordBBox bbox;                 // of active values, from the tree (never file metadata)
    openvdb::Vec3d voxel_size;
    size_t bricks = 0;                       // 8^3 bricks the active values occupy
    size_t brick_bytes = 0;                  // what those bricks take in the atlas, one float channel
    UpAxisGuess up;
    int index = 0;                           // among the file's grids of the same name (volume.density.index)
    bool has_range = false;                  // scalar and vector grids with active values
    bool vector = false;                     // the range is of the vectors' lengths
    double min_value = 0.0, max_value = 0.0; // of the active values (tiles included)
    glm::vec3 world_min{0.0f}, world_max{0.0f};   // the active bbox's world-space box
    std::string damaged_metadata;            // how the file's bbox metadata contradicts the voxels, or ""
};

void initOpenVdb();

// The grids `spec` names, each of its emission sources' grids, and with motion blur the velocity
// grid, in the file's own world: spec.transform is applied after the bricks (placedVolume, the
// kernel inputs). Throws InputError "<file>: <problem>".
LoadedVolume loadVolume(const std::string& file, const VolumeSpec& spec,
                        const std::optional<MotionBlur>& motion = std::nullopt);

// `volume` where `placement` puts it: its index-to-world and the default view's up frame. The
// velocity grid keeps the file's world units (the kernel turns it: VxParams::velocity_to_world).
LoadedVolume placedVolume(LoadedVolume volume, const glm::mat4& placement);
std::vector<GridSummary> summarizeFile(const std::string& file);

// Index-to-world of a grid as a column-major matrix; throws for non-affine transforms.
glm::mat4 indexToWorld(const openvdb::GridBase& grid, const std::string& file);

// Smallest world length of one voxel edge: the march step unit.
float voxelEdge(const glm::mat4& index_to_world);

// World-space axis-aligned box of the voxels of index box `box` (OpenVDB's inclusive bounds, as
// evalActiveVoxelBoundingBox gives them) under `index_to_world`.
void voxelBoxWorldBounds(const glm::mat4& index_to_world, const openvdb::CoordBBox& box, glm::vec3& lo, glm::vec3& hi);

}  // namespace voxlux
