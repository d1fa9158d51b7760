// Environment lights as the renderers take them (docs/environment.md). Each enabled environment
// light's map is read (an OpenEXR's R, G, B through OCIO from map_colorspace into the working
// space), oriented about its up and scaled by its colour and intensity, for the reference's
// importance sampling and the camera's background. For the march's fast methods the light becomes
// median-cut directional lights and an ambient remainder (optics/median_cut.h), which every method
// takes as it takes any light, and which propagation carries as one coherent group per sweep
// direction (Sunden 2015). Maps and cuts are kept between calls by the file's identity, so that a
// rotation or a new intensity makes no new cut: it turns or scales the K lights, and orients a
// copy of the map with its sampling tables (O(pixels)).
#pragma once
#include "scene/scene.h"

namespace voxlux {

// `scene` with its environment lights' maps loaded (EnvironmentSettings::loaded) and, unless it
// renders the reference, their median-cut lights and remainders appended (Light::from_environment).
// Throws InputError naming the map for a file that cannot be read or a colour space the config
// lacks. Pixels that are NaN or infinite are taken as black, channels below 0 as 0, and counted
// (EnvironmentSettings::repaired_pixels).
Scene withEnvironmentLights(Scene scene);

// The world up an environment light without `up` takes: the first volume's up (volume.up, or what
// its file's metadata says; y when it says nothing).
glm::vec3 defaultEnvironmentUp(const Scene& scene);

}  // namespace voxlux
