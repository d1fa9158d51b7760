#include "volume/velocity.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <openvdb/tools/Morphology.h>

#include "core/error.h"
#include "vx_prelude.h"
#include "volume/vdb_loader.h"

namespace voxlux {

const std::vector<std::string>& velocityGridNames() {
    static const std::vector<std::string> names{"vel", "v", "velocity"};
    return names;
}

openvdb::Vec3SGrid::Ptr velocityAtVoxelCentres(openvdb::Vec3SGrid::Ptr grid) {
    if (grid->getGridClass() != openvdb::GRID_STAGGERED) return grid;
    openvdb::Vec3SGrid::Ptr centred = grid->deepCopy();
    centred->setGridClass(openvdb::GRID_UNKNOWN);
    const auto faces = grid->getConstAccessor();
    for (auto it = centred->beginValueOn(); it; ++it) {
        const openvdb::Coord c = it.getCoord();
        const openvdb::Vec3s low = faces.getValue(c);
        const openvdb::Vec3s high(faces.getValue(c.offsetBy(1, 0, 0)).x(), faces.getValue(c.offsetBy(0, 1, 0)).y(),
                                  faces.getValue(c.offsetBy(0, 0, 1)).z());
        it.setValue((low + high) * 0.5f);
    }
    return centred;
}

float maxSpeed(const openvdb::Vec3SGrid& grid) {
    double top = 0.0;
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        const openvdb::Vec3d v(*it);   // in double: finite components always have a finite length
        if (std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z())) top = std::max(top, v.length());
    }
    return float(std::min(top, double(std::numeric_limits<float>::max())));
}

float motionReachVoxels(float max_speed, float voxel, const MotionBlur& motion, const std::string& file, const std::string& grid) {
    const double frames = std::max(std::abs(motion.shutter_open), std::abs(motion.shutter_close));
    const double voxels = double(max_speed) * std::abs(motion.velocity_scale) / motion.fps * frames / voxel;
    constexpr double kMaxVoxels = 32.0 * VX_BRICK;
    if (!(voxels <= kMaxVoxels))
        throw InputError(file + ": grid '" + grid + "' moves the medium up to " + std::to_string(int(std::min(voxels, 1e9))) +
                         " voxels within the shutter (more than " + std::to_string(int(kMaxVoxels)) +
                         "); check render.motion_blur.velocity_scale and fps");
    return float(voxels);
}

void extendVelocity(openvdb::Vec3SGrid& grid, int voxels) {
    std::vector<std::pair<openvdb::Coord, openvdb::Vec3s>> layer;
    for (int step = 0; step < voxels; ++step) {
        openvdb::MaskGrid known;
        known.tree().topologyUnion(grid.tree());
        openvdb::tools::dilateActiveValues(grid.tree(), 1, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
        openvdb::MaskGrid fresh;   // the layer just activated
        fresh.tree().topologyUnion(grid.tree());
        fresh.tree().topologyDifference(known.tree());
        const auto was = known.getConstAccessor();
        const auto values = grid.getConstAccessor();
        layer.clear();
        for (auto it = fresh.cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            openvdb::Vec3s sum(0.0f);
            int count = 0;
            for (int n = 0; n < 27; ++n) {
                const openvdb::Coord q = c.offsetBy(n % 3 - 1, n / 3 % 3 - 1, n / 9 - 1);
                const openvdb::Vec3s v = values.getValue(q);
                if (was.isValueOn(q) && std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z())) sum += v, ++count;
            }
            layer.emplace_back(c, count ? sum / float(count) : openvdb::Vec3s(0.0f));
        }
        if (layer.empty()) return;
        auto out = grid.getAccessor();
        for (const auto& [c, v] : layer) out.setValue(c, v);
    }
}

int motionReachBricks(const LoadedVolume& volume, const std::optional<MotionBlur>& motion) {
    if (!motion || !volume.velocity) return 0;
    const float voxels = motionReachVoxels(volume.max_speed, voxelEdge(volume.index_to_world), *motion, volume.file,
                                           volume.velocity->getName());
    return int(std::ceil(voxels / VX_BRICK));
}

}  // namespace voxlux
