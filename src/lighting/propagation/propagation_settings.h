// Illumination propagation's settings (Ropinski 2010, Kniss 2003), the scene's effects keys it
// owns: propagation (the illumination volume of effects.shadows "propagation") and indirect (the
// multiply scattered light swept through it). Read, validated and written here
// (propagation_settings.cpp); the scene holds them through the generated MethodSettings
// (cmake/method_settings.cmake). Cost: none, plain data.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "scene/filter.h"

namespace voxlux {

class JsonObject;

// Knobs of the illumination volume; its resolution and memory budget are effects.light_resolution
// and light_memory_mb, as for the SAT.
struct Propagation {
    bool blend_axes = false;               // also sweep the second closest face axis and blend
    bool eye_pass = false;                 // a second sweep scattering light towards the camera
    bool chroma_subsampling = false;       // indirect light at half the resolution per axis
    bool coherent = true;                  // all lights of a propagation direction in one pass (Sunden
                                           // 2015); false: one pass per light. Same result, for timing
    Filter filter = Filter::Tricubic;      // how the march reads the volume between cells: the B-spline
                                           // leaves no bands at the cells (docs/accuracy.md)
};

// Indirect (multiply scattered) light, swept through the illumination volume, blurred within a cone
// as it propagates (Kniss 2003 Eq. 9). Needs shadows "propagation". How deep it reaches and how
// bright it is come from the model: "diffusion" derives both from the material's albedo and
// anisotropy (src/optics/diffusion_profile.h), and scales the sky's light as diffusion theory does;
// "kniss" is Kniss 2003 Eq. 8: an artist's transport colour.
enum class BlurPhase { Phong, HenyeyGreenstein };
enum class IndirectModel { Diffusion, Kniss };

struct Indirect {
    IndirectModel model = IndirectModel::Diffusion;
    float strength = 1.0f;                 // scale of the indirect term in Kniss Eq. 12
    float angle = 30.0f;                   // blur cone apex angle, degrees (Kniss theta)
    int samples = 9;                       // blur taps per cell
    BlurPhase phase = BlurPhase::Phong;    // tap weights: Phong lobe cos^exponent, or Henyey-Greenstein g
    float exponent = 4.0f;
    float g = 0.5f;
    glm::vec3 transport_color{0.6f};       // kniss: share of indirect light kept per unit optical depth
                                           // (direct keeps e^-1 = 0.37: indirect light reaches deeper)
};

struct PropagationSettings {
    Propagation propagation;
    std::optional<Indirect> indirect;

    // The effects keys above.
    static std::vector<std::string> keys();
};

// From the scene's effects object; throws InputError naming the key of a bad value.
void readSettings(const JsonObject& effects, PropagationSettings& settings);
// Into the scene's effects object, every value the method reads.
void writeSettings(const PropagationSettings& settings, nlohmann::json& effects);

}  // namespace voxlux
