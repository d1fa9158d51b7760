#include "render/framing.h"

#include <cmath>
#include <optional>

#include "core/error.h"
#include "core/frame_pattern.h"
#include "scene/camera.h"
#include "volume/vdb_loader.h"
#include "volume/volume_stages.h"

namespace voxlux {
namespace {

// Only the density grid: the other grids do not move the framing.
VolumeSpec densityOnly(const VolumeSpec& spec) {
    VolumeSpec v = spec;
    v.color.reset();
    v.emission.clear();
    return v;
}

}  // namespace

Camera frameVolumeCamera(const std::string& file, const Scene& scene) {
    const LoadedVolume volume = placedVolume(loadVolume(file, densityOnly(scene.volume())), volumePlacement(scene.volume(), std::nullopt));
    if (volume.density->activeVoxelCount() == 0)
        throw InputError(file + ": grid '" + volume.density->getName() + "' has no active voxels");
    return frameActiveVoxels(volume, scene);
}

SequenceFraming frameSequence(const Scene& scene) {
    FrameSet frames;
    try {
        frames = framesOnDisk(scene.volume().path, scene.volume().frames.value());
    } catch (const std::invalid_argument& e) {
        throw InputError(scene.volume().path + ": " + e.what());
    }
    if (frames.count() == 0) throw InputError(scene.volume().path + ": no file of this sequence exists");
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    std::optional<glm::mat3> view;
    SequenceFraming out;
    openvdb::Index64 most = 0;
    for (int64_t k = 0; k < frames.count(); ++k) {
        const int frame = frames.at(k);
        // A frame that cannot be read (a file still being written, a damaged one) frames nothing;
        // the render names it when its turn comes.
        LoadedVolume volume;
        try {
            volume = placedVolume(loadVolume(expandFramePattern(scene.volume().path, frame), densityOnly(scene.volume())),
                                  volumePlacement(scene.volume(), frame));
        } catch (const InputError& e) {
            if (out.unreadable.count() == 0) out.unreadable_reason = e.what();
            out.unreadable.add(frame);
            continue;
        }
        const openvdb::CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
        if (box.empty()) continue;
        if (volume.density->activeVoxelCount() > most) most = volume.density->activeVoxelCount(), out.fullest_frame = frame;
        glm::vec3 frame_lo, frame_hi;
        voxelBoxWorldBounds(volume.index_to_world, box, frame_lo, frame_hi);
        lo = glm::min(lo, frame_lo);
        hi = glm::max(hi, frame_hi);
        if (!view) view = viewFrameOf(scene, volume);
    }
    if (!view)
        throw InputError(scene.volume().path + ": frames " + frames.text() +
                         " have no active voxels in grid '" + scene.volume().density.name + "' to frame");
    out.frames = frames;
    out.camera = frameBox(lo, hi, Camera{}.fov, float(scene.render.width) / float(scene.render.height), *view);
    return out;
}

}  // namespace voxlux
