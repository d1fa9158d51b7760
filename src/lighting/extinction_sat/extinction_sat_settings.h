// Extinction-SAT lighting's settings (Schlegel 2011), the scene's effects keys it owns:
// ambient_occlusion (AO shells), color_bleeding and cone (the shadow cones of effects.shadows
// "sat_cone"). Read, validated and written here (extinction_sat_settings.cpp); the scene holds them
// through the generated MethodSettings (cmake/method_settings.cmake). Cost: none, plain data.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace voxlux {

class JsonObject;

struct AmbientOcclusion {
    int shells = 3;
    float radius = 0.0f;                   // world units; 0 = 6% of the light grid's longest side
};

struct ShadowCone {
    float angle = 2.0f;                    // half-angle, degrees
    int samples = 20;                      // cuboids per cone
    float growth = 0.05f;                  // each cuboid this much longer than the one before
};

struct ExtinctionSatSettings {
    std::optional<AmbientOcclusion> ambient_occlusion;
    float color_bleeding = 0.0f;           // 0..1: how much the neighbourhood's albedo tints AO
    ShadowCone cone;

    // The effects keys above.
    static std::vector<std::string> keys();
};

// From the scene's effects object; throws InputError naming the key of a bad value.
void readSettings(const JsonObject& effects, ExtinctionSatSettings& settings);
// Into the scene's effects object, every value the method reads.
void writeSettings(const ExtinctionSatSettings& settings, nlohmann::json& effects);

}  // namespace voxlux
