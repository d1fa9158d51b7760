// Grade stage, colour side: the OpenColorIO config a scene renders under and the processors the
// grade stage applies (docs/color.md). Built once per scene; the backends run the processors
// (CPU processor on the cpu backend, GPU shader generation on gl).
#pragma once
#include <optional>
#include <string>

#include <OpenColorIO/OpenColorIO.h>
#include <glm/glm.hpp>

#include "scene/scene.h"

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
    bool unpremultiply = true;             // of the beauty, around the grade and the output conversion
    // The beauty goes through `grade` then `output`; the colour AOVs only through `output` (they
    // stay ungraded, as compositors expect); the preview applies `preview` to the graded beauty.
    OCIO::ConstProcessorRcPtr grade;       // the grade steps, working -> working (may be a no-op)
    OCIO::ConstProcessorRcPtr output;      // working -> output space (a no-op when they are one)
    OCIO::ConstProcessorRcPtr preview;     // working -> display/view; null unless asked for
    std::optional<Chromaticities> output_chromaticities;  // set when the output space is linear RGB
    std::optional<glm::mat3> xyz_to_working;  // CIE XYZ (D65 white) -> working; unset when the config
                                              // has no cie_xyz_d65_interchange role
};

// The config a scene uses: color.config (resolved against the scene folder when parsed), else
// $OCIO, else the config built into voxlux (ocio/voxlux.ocio). Throws InputError naming the file.
OCIO::ConstConfigRcPtr loadColorConfig(const ColorSettings& color, std::string& source);

// The canonical name of a colour space given by name, alias or role; throws InputError
// "<key>: no colour space 'X' in <source> (it has: A, B, ...)".
std::string requireColorSpace(const OCIO::Config& config, const std::string& name, const std::string& key,
                              const std::string& source);

// Resolves spaces, looks and files and builds the processors (the preview's only when
// `with_preview` or the scene names a display). Throws InputError with a one-line message naming
// what is missing and what exists ("color.output_space: no colour space 'X' in <config> (it has:
// A, B, ...)").
ColorPipeline buildColorPipeline(const ColorSettings& color, bool with_preview);

// The two halves of buildColorPipeline: the config and working space (with xyz_to_working), which
// the march needs, and the transforms over them, which only the grade needs; each throws as above.
ColorPipeline resolveWorkingSpace(const ColorSettings& color);
ColorPipeline buildColorTransforms(ColorPipeline working, const ColorSettings& color, bool with_preview);

}  // namespace voxlux
