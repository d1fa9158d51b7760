// `voxlux render` over a scene's frames, as a farm runs it: each frame rendered through one
// Renderer, so the render graph keeps whatever a frame change leaves valid; frames whose outputs
// are done skipped (--resume); a failed frame reported and passed over (unless --fail-fast); one
// JSON line per frame (--log-json); a progress bar with the frames done, the time left and the
// stage running. Cost: that of the frames, plus one read of each done EXR when resuming.
#pragma once
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "core/frame_set.h"
#include "scene/scene.h"

namespace voxlux {

// The exit code when some frames failed and the others were rendered (docs/farm.md).
constexpr int kFramesFailed = 3;

struct SequenceOptions {
    bool resume = false;                   // skip frames whose outputs checkFrame finds done
    bool fail_fast = false;                // stop at the first failed frame
    std::optional<std::string> log_json;   // append one JSON line per frame here
    std::optional<std::string> stats;      // write per-stage times and peak memory here at the end
};

// The frames `scene` renders: volume.frames for a #### volume path, none for one file. Throws
// InputError when a pattern has no frames, or several frames would share one output path.
std::optional<FrameSet> sequenceFrames(const Scene& scene);

// The time the `frames_left` frames after these will take, from the rendered frames' own times in
// order: a straight line through them (least squares), extended over the frames left, so that a
// simulation that grows frame by frame is not under-estimated by the mean of its small first
// frames; the last frame's time for each frame left until three have rendered.
double sequenceSecondsLeft(const std::vector<double>& frame_seconds, int64_t frames_left);

// Renders and writes every frame; what it does goes to `out` (one line a frame) and warnings and
// frame errors to `err`. Returns 0, or kFramesFailed after naming the failed frames. A scene of one
// file (no frames) that fails throws its InputError, as any render does.
int renderSequence(const Scene& scene, const SequenceOptions& options, std::ostream& out, std::ostream& err);

}  // namespace voxlux
