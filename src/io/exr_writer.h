// Write stage: scene-linear, premultiplied RGBA plus the requested AOV layers to OpenEXR, via a
// temporary file renamed into place, so a failed or interrupted render never leaves a partial file.
#pragma once
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_backend.h"
#include "scene/scene.h"

namespace voxlux {

struct ExrMetadata {
    glm::mat4 world_to_camera{1.0f};
    glm::mat4 world_to_ndc{1.0f};
    std::string scene_hash;
    std::optional<int> frame;
    std::vector<std::pair<std::string, double>> stage_seconds;
    // OpenEXR has no standard colour-space attribute: the name goes to oiio:ColorSpace (read by
    // OpenImageIO-based tools) and voxlux/colorSpace; "" writes neither.
    std::string color_space;
    std::string color_config;              // the OCIO config's name or path, as voxlux/config; "" = none
    float exposure = 0.0f;                 // stops applied before the output transform, as voxlux/exposure
    std::optional<std::array<glm::vec2, 4>> chromaticities;  // CIE xy of red, green, blue, white
    std::vector<std::string> light_groups; // the light-group layers, as voxlux/lightGroups ("lightgroup.key", ...)
};

struct ExrWriteReport {
    size_t non_finite = 0;     // samples that were NaN/Inf and written as 0 (should stay 0)
    size_t half_overflow = 0;  // samples above the half-float range, written as 65504
};

// A plane of a layer that is not part of the pixels: the coverage AOV's, one per volume.
struct ExrPlane {
    std::string name;                      // its channel in the layer ("smoke" in coverage.smoke)
    const std::vector<float>* values;      // one per pixel, as RenderImage::pixels
};

// Throws InputError "<path>: ..." when the file cannot be written; nothing is left at `path` then.
// `coverage`: the planes of the "coverage" AOV, when spec.aovs has it.
ExrWriteReport writeExr(const std::string& path, const RenderImage& image, const OutputSpec& spec,
                        const ExrMetadata& meta, const std::vector<ExrPlane>& coverage = {});

// Calls `write` with a temporary path in the same folder, then renames it to `path`. On any
// failure the temporary file is removed and InputError "<path>: cannot write in folder F: <cause>"
// (no file can be made there) or "<path>: cannot write (...)" is thrown, naming `path`, never the
// temporary.
// A `path` that exists and is not a regular file is never replaced: a device or pipe
// (/dev/null) is written in place, a folder is refused. Temporaries of `path` that a killed
// voxlux left (their process no longer runs on this machine) are removed first.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);
void writeFileAtomically(const std::string& path, const std::string& bytes);

// Why `path` could not be written, without touching anything: "<path>: cannot create folder F:
// <cause>" for a folder that is missing and cannot be made (its nearest existing ancestor is not
// a folder, or is not writable: a read-only file system), "<path>: cannot write in folder F:
// <cause>", "<path>: is a folder, not a file"; nullopt when it can. For --explain.
std::optional<std::string> outputProblem(const std::string& path);

// Makes the folders `path` needs; throws outputProblem's "cannot create folder" line.
void makeOutputFolder(const std::string& path);

// makeOutputFolder, then throws the InputError writeAtomically would give for `path`'s folder,
// leaving no file behind: for the outputs of a run, checked before its first frame.
void checkWritable(const std::string& path);

}  // namespace voxlux
