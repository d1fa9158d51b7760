// Which world axis is up in a cache, as the file says it. OpenVDB has no up-axis field, so this
// reads what each writer leaves: Blender writes Z-up domain-local grids (Mantaflow's
// `file_base_resolution` on every grid since 2.82, `creator` "Blender/..." or `is_local_space`
// without a creator in the older smoke cache); Houdini, EmberGen and OpenVDB's own tools are Y-up.
// Costs a few metadata lookups.
#pragma once
#include <string>

#include <openvdb/openvdb.h>

namespace voxlux {

struct UpAxisGuess {
    int axis = 1;           // 0 x, 1 y, 2 z
    std::string reason;     // what in the file said so, for `info` and the quick form's note
};

UpAxisGuess detectUpAxis(const openvdb::MetaMap& file_metadata, const openvdb::MetaMap& grid_metadata);

}  // namespace voxlux
