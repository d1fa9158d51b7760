// Whether a frame's outputs are done: its EXR exists, reads whole, and carries the scene's hash
// (voxlux/sceneHash, src/render/write_stage.h) and the frame's number (voxlux/frame), and its preview PNG and deep EXR exist when the
// scene asks for them (they are written before the EXR, which is renamed into place last). `render --resume` skips such frames and `farm collect` accepts them. Cost: one read of the
// EXR (milliseconds at 512^2), since only a full read finds a file cut short.
#pragma once
#include <optional>
#include <string>

#include "scene/scene.h"

namespace voxlux {

struct FrameCheck {
    enum class State { Done, Missing, Corrupt, OtherScene };
    State state = State::Missing;
    std::string path;     // the EXR checked
    std::string reason;   // for any state but Done, one line: "out.0003.exr: rendered from another scene"
};

// `hash` is sceneHash(scene), computed once by the caller for a whole sequence.
FrameCheck checkFrame(const Scene& scene, std::optional<int> frame, const std::string& hash);

const char* frameStateName(FrameCheck::State state);   // "done", "missing", "corrupt", "other-scene"

}  // namespace voxlux
