// Fuzzes the Nuke .chan reader and poses a transform at frames between and beyond its keys: the
// input is a .chan file's text. Bad input must throw InputError; anything else is a defect.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "scene/chan_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        voxlux::VolumeTransform t;
        t.keys = voxlux::parseChan(std::string(reinterpret_cast<const char*>(data), size), "fuzz.chan").keys;
        for (const double frame : {t.keys.front().frame - 1.0, 0.5 * (t.keys.front().frame + t.keys.back().frame), t.keys.back().frame + 1.0}) {
            const glm::mat4 m = voxlux::volumeTransformMatrix(t, frame);
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    if (!std::isfinite(m[c][r])) std::abort();   // finite keys pose finitely
        }
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
