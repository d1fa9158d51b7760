// The light panel's picture of an environment light: its map as the file lays it out (row 0 faces
// `up`, the centre column the frame's x), shrunk to at most 256 x 128 by box filtering, exposed so
// that its mean luminance shows as mid grey through the scene's display and view, with a dot at
// each median-cut light (the fast methods' K directional lights: docs/environment.md) sized by its
// share of their power. The map and its cut come from the render's caches, so a thumbnail costs a
// pass over the map's pixels; the viewer makes one only when the map, its colour space or K change.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "viewer/display_texture.h"

namespace voxlux {

struct EnvironmentThumbnail {
    int width = 0, height = 0;
    std::vector<uint8_t> texels;   // RGBA, row 0 at the top
    struct CutPoint {
        glm::vec2 uv;              // in [0, 1]^2 across and down the map
        float share;               // of the K lights' summed luminance
    };
    std::vector<CutPoint> cut;
};

// The thumbnail of scene.lights[light], an environment light. Throws InputError as the render
// would (a map that cannot be read, a colour space the config lacks).
EnvironmentThumbnail environmentThumbnail(const Scene& scene, size_t light);

// The panel's widget: the thumbnail at the panel's width with its dots. Remakes the GL texture
// when the map, its colour space, K or the display change; a map that cannot be read shows its
// error instead.
class EnvironmentThumbnailWidget {
public:
    void draw(const Scene& scene, size_t light);

private:
    DisplayTexture texture_;
    std::string key_, error_;
    EnvironmentThumbnail shown_;
};

}  // namespace voxlux
