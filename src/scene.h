// The scene: everything a render needs, as parsed from JSON (docs/scene.md) or built by the quick
// form of `voxlux render cache.vdb`. Plain data; parsing and validation live in scene_json.cpp.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace voxlux {

// A grid chosen by name; `index` picks among several grids with the same name.
struct GridRef {
    std::string name;
    int index = 0;
    bool operator==(const GridRef&) const = default;
};

enum class LevelSetPolicy { Reject, ConvertToFog };

struct VolumeSpec {
    std::string path;                      // may contain a #### frame pattern
    std::optional<std::array<int, 2>> frames;  // inclusive range for a #### pattern
    GridRef density{"density", 0};
    std::optional<GridRef> emission;       // temperature / heat / flame
    std::optional<GridRef> color;          // Cd, vec3
    LevelSetPolicy level_set = LevelSetPolicy::Reject;
};

struct TransferPoint {
    float value = 0.0f;
    float extinction = 0.0f;
    glm::vec3 albedo{1.0f};
};

struct Material {
    float density_scale = 1.0f;            // grid value -> extinction per world unit
    glm::vec3 albedo{0.9f};
    float anisotropy = 0.0f;               // Henyey-Greenstein g
    glm::vec3 emission_color{1.0f};
    float emission_scale = 1.0f;
    std::vector<TransferPoint> transfer;   // empty: extinction = density * density_scale
};

// Ambient is uniform light from every direction (radiance color * intensity), occluded only when
// effects.ambient_occlusion is on.
enum class LightType { Directional, Point, Spot, Ambient };

struct Light {
    LightType type = LightType::Directional;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // the way the light travels
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float cone_angle = 30.0f;              // spot: outer half-angle, degrees
    float cone_softness = 5.0f;            // spot: degrees of falloff inside the outer angle
};

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 look_at{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    std::optional<glm::mat4> matrix;       // camera-to-world; overrides position/look_at/up
    float fov = 40.0f;                     // vertical, degrees
};

enum class Backend { Auto, Cpu, Gl };

struct RenderSettings {
    int width = 512;
    int height = 512;
    float step = 0.5f;                     // voxels (of the smallest voxel edge)
    float shadow_step = 1.0f;              // voxels, for ray-marched shadows
    float transmittance_cutoff = 1e-4f;
    Backend backend = Backend::Auto;
};

// Raymarch: a shadow ray per sample and light (the reference). SatCone: Schlegel 2011 cones of
// SAT cuboids, precomputed into the light cache.
enum class ShadowMethod { None, Raymarch, SatCone };

struct AmbientOcclusion {
    int shells = 3;
    float radius = 0.0f;                   // world units; 0 = 6% of the light grid's longest side
};

struct ShadowCone {
    float angle = 2.0f;                    // half-angle, degrees
    int samples = 20;                      // cuboids per cone
    float growth = 0.05f;                  // each cuboid this much longer than the one before
};

struct Effects {
    ShadowMethod shadows = ShadowMethod::Raymarch;
    std::optional<AmbientOcclusion> ambient_occlusion;
    float color_bleeding = 0.0f;           // 0..1: how much the neighbourhood's albedo tints AO
    ShadowCone cone;
    int light_resolution = 128;            // light-grid cells along the volume's longest side
    int light_memory_mb = 2048;            // budget for light grid, SAT and light cache
};

enum class PixelType { Half, Float };

struct OutputSpec {
    std::string path;                      // may contain #### for sequences
    PixelType pixel_type = PixelType::Half;
    std::string compression = "zip";
    std::vector<std::string> aovs;         // subset of direct, emission, transmittance, depth
};

struct Scene {
    VolumeSpec volume;
    Material material;
    std::vector<Light> lights;
    std::optional<Camera> camera;          // absent: framed from the volume's bounding box
    RenderSettings render;
    Effects effects;
    OutputSpec output;
};

const std::vector<std::string>& knownAovs();

}  // namespace voxlux
