// Nuke's .chan file, the text an Axis or a Camera exports: one line per frame,
// "frame tx ty tz rx ry rz", rotations in degrees. A camera's file carries its vertical field of
// view (degrees) in an eighth column, which a volume's placement has no use for and skips. Reading
// is one pass over the text; each key costs a line.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace voxlux {

struct ChanTrack {
    std::vector<TransformKey> keys;        // frames strictly increasing, scale 1
    std::vector<float> vertical_fov;       // per key, a camera's eighth column; empty unless every line has one
};

// The keys of `text` (read from `file`). Blank lines are skipped. Throws InputError
// "<file>: line N: <problem>" for anything else, and for a file without a key.
ChanTrack parseChan(const std::string& text, const std::string& file);

// parseChan of the file at `path`; throws InputError "<path>: cannot open .chan file" when it
// cannot be read.
ChanTrack readChanFile(const std::string& path);

}  // namespace voxlux
