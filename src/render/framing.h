// The default camera when a scene has none: one volume framed by its active voxels, and a
// sequence framed once, on the union of the active voxels of every frame of it on disk, so the
// camera holds still while the volume grows, and is the same whichever frames a render asks for
// (two artists' halves of a shot, a farm's chunks, cut together). Framing a sequence reads each
// frame's density grid once (its voxels and tree, not the other grids): about 5 ms a frame for a
// Blender fire at resolution 64.
#pragma once
#include <string>

#include "core/frame_set.h"
#include "scene/scene.h"

namespace voxlux {

// Frames the active voxels of the density grid of `file`.
Camera frameVolumeCamera(const std::string& file, const Scene& scene);

struct SequenceFraming {
    Camera camera;
    FrameSet frames;         // the frames on disk, framed together
    int fullest_frame = 0;   // the one with the most active voxels
    FrameSet unreadable;     // frames on disk left out, as they cannot be read
    std::string unreadable_reason;   // the first one's error
};

// Frames every frame on disk of the scene's #### volume path together (framesOnDisk), whatever
// volume.frames says; empty frames count for nothing. Throws InputError when no file exists or
// every frame is empty.
SequenceFraming frameSequence(const Scene& scene);

}  // namespace voxlux
