#include "tools/frame_check.h"

#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfStringAttribute.h>

#include <filesystem>

#include "core/error.h"
#include "core/frame_pattern.h"
#include "io/exr_reader.h"

namespace voxlux {

FrameCheck checkFrame(const Scene& scene, std::optional<int> frame, const std::string& hash) {
    const auto expand = [&](const std::string& p) { return frame ? expandFramePattern(p, *frame) : p; };
    FrameCheck c;
    c.path = expand(scene.output.path);
    if (!std::filesystem::exists(c.path)) {
        c.reason = c.path + ": not rendered";
        return c;
    }
    try {
        readExrRgba(c.path);   // every scanline: a file cut short fails here, not at its header
        const Imf::InputFile file(c.path.c_str());
        const auto* written = file.header().findTypedAttribute<Imf::StringAttribute>("voxlux/sceneHash");
        if (!written || written->value() != hash) {
            c.state = FrameCheck::State::OtherScene;
            c.reason = c.path + ": rendered from another scene (voxlux/sceneHash " + (written ? written->value() : "missing") +
                       ", this scene's " + hash + ")";
            return c;
        }
        // One output path may serve several frames (--frames 5 -o out.exr, then --frames 6).
        const auto* written_frame = file.header().findTypedAttribute<Imf::IntAttribute>("voxlux/frame");
        if (frame.has_value() != (written_frame != nullptr) || (frame && written_frame->value() != *frame)) {
            c.state = FrameCheck::State::OtherScene;
            c.reason = c.path + ": holds " + (written_frame ? "frame " + std::to_string(written_frame->value()) : std::string("no frame")) +
                       ", not " + (frame ? "frame " + std::to_string(*frame) : std::string("a single file"));
            return c;
        }
    } catch (const std::exception& e) {
        c.state = FrameCheck::State::Corrupt;
        c.reason = e.what();
        return c;
    }
    if (!scene.output.preview.empty() && !std::filesystem::exists(expand(scene.output.preview))) {
        c.reason = expand(scene.output.preview) + ": preview not written";
        return c;
    }
    if (scene.output.deep && !std::filesystem::exists(deepPath(c.path))) {
        c.reason = deepPath(c.path) + ": deep image not written";
        return c;
    }
    c.state = FrameCheck::State::Done;
    return c;
}

const char* frameStateName(FrameCheck::State state) {
    switch (state) {
        case FrameCheck::State::Done: return "done";
        case FrameCheck::State::Missing: return "missing";
        case FrameCheck::State::Corrupt: return "corrupt";
        case FrameCheck::State::OtherScene: return "other-scene";
    }
    return "";
}

}  // namespace voxlux
