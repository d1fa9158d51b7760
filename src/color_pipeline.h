// Grade stage, colour side: the OpenColorIO config a scene renders under and the processors the
// grade stage applies (docs/color.md). Built once per scene; the backends run the processors
// (CPU processor on the cpu backend, GPU shader generation on gl).
#pragma once
#include <optional>
#include <string>

#include <OpenColorIO/OpenColorIO.h>
#include <glm/glm.hpp>

#include "scene.h"

namespace OCIO = OCIO_NAMESPACE;

namespace voxlux {

// CIE xy of an RGB space's primaries and white, as the EXR `chromaticities` attribute holds them.
struct Chromaticities {
    glm::vec2 red, green, blue, white;
};

struct ColorPipeline {
    OCIO::ConstConfigRcPtr config;
    std::string config_source;             // the config file, or "voxlux built-in config"
    std::string working_space;
    std::string output_space;
    std::string display, view;             // the preview's, resolved
    bool unpremultiply = true;
    OCIO::ConstProcessorRcPtr beauty;      // the grade steps, then working -> output space
    OCIO::ConstProcessorRcPtr aovs;        // working -> output space (AOVs stay ungraded)
    OCIO::ConstProcessorRcPtr preview;     // the grade steps, then working -> display/view
    bool beauty_is_identity = true;        // nothing to do for the beauty (no grade, output = working)
    bool aovs_are_identity = true;
    std::optional<Chromaticities> output_chromaticities;  // set when the output space is linear RGB
    glm::mat3 xyz_to_working{1.0f};        // CIE XYZ (D65 white) -> working space, for blackbody emission
};

// The config a scene uses: color.config (resolved against the scene folder when parsed), else
// $OCIO, else the config built into voxlux (ocio/voxlux.ocio). Throws InputError naming the file.
OCIO::ConstConfigRcPtr loadColorConfig(const ColorSettings& color, std::string& source);

// Resolves spaces, looks and files and builds the processors. Throws InputError with a one-line
// message naming what is missing and what exists ("color.output_space: no colour space 'X' in
// <config> (it has: A, B, ...)").
ColorPipeline buildColorPipeline(const ColorSettings& color);

}  // namespace voxlux
