// `voxlux make-cloud`: a procedural cumulus (blended spheres eroded by fBm value noise), so the
// project ships a default volume it made itself. Deterministic for a given seed.
#pragma once
#include <cstdint>

#include <openvdb/openvdb.h>

namespace voxlux {

struct CloudParams {
    int resolution = 96;      // voxels across the cloud's longest axis
    uint32_t seed = 1;
    float world_size = 2.0f;  // world units across the longest axis
};

openvdb::FloatGrid::Ptr makeCloud(const CloudParams& params);

}  // namespace voxlux
