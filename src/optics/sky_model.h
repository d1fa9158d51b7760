// Skies voxlux makes itself (`voxlux make-sky`), so a fresh clone lights a cloud without
// downloading a map: a clear sky from Preetham, Shirley and Smits 1999 (the Perez luminance and
// chromaticity distributions fitted to turbidity and the sun's height), with the sun's disc as one
// pixel carrying its illuminance; an overcast sky from the CIE standard overcast distribution,
// (1 + 2 cos theta) / 3 of the zenith luminance; and the ground below the horizon as a grey
// Lambertian reflector of the sky and sun above it. Values are CIE XYZ (D65 white) in units of
// 10 kcd/m^2: a clear noon zenith is about 0.7, the sun's illuminance about 10.
#pragma once
#include <vector>

#include <glm/glm.hpp>

namespace voxlux {

enum class SkyKind { Clear, Overcast };

struct SkyParams {
    SkyKind kind = SkyKind::Clear;
    float sun_elevation = 35.0f;   // degrees above the horizon (clear)
    float sun_azimuth = 0.0f;      // degrees from the map's centre column, towards its left quarter
    float turbidity = 3.0f;        // 2 (very clear) .. 10 (hazy)
    float ground_albedo = 0.3f;
    bool sun_disc = true;          // false: the sky alone, for a scene whose sun is a directional light of its own
    int width = 512, height = 256;
};

// The sky as a lat-long map, row 0 at the top (up), in CIE XYZ; the orientation is
// optics/environment_map.h's.
std::vector<glm::vec3> makeSky(const SkyParams& params);

// The unit direction of the sun in the map's frame (x the centre column, y its left quarter, z up).
glm::vec3 sunDirection(const SkyParams& params);

}  // namespace voxlux
