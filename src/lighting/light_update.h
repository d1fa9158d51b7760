// What a lighting method's update of its lights did in a frame (the propagation's sweeps, updated
// selectively when only lights change: Ropinski 2010's illumination volume, Sunden 2015's light
// groups): what a frame reports (LightingMethod::lightUpdate), the light-edit report prints and the
// tests check. Its own header, so that what reads a report compiles no method's stages.
#pragma once
#include <string>

namespace voxlux {

struct LightUpdate {
    enum class Mode { Kept, Entire, Selective };
    Mode mode = Mode::Entire;
    std::string reason;          // why this mode (empty when kept)
    int lights = 0;              // lights in the volume afterwards
    int lights_out = 0;          // light states taken out (selective: the changed lights' old states)
    int lights_in = 0;           // light states put in (selective: their new states; entire: all lights)
    int sweeps = 0;              // light sweeps run, over both blocks (a light in two passes counts twice)
    int passes = 0;              // passes over the volume
    long long slices = 0;        // slices walked, over all passes
    double selective_cost = 0;   // the estimates compared (units: cells times a directional sweep's work)
    double entire_cost = 0;
};

}  // namespace voxlux
