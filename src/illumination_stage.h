// Illumination stage (Ropinski 2010 with the Kniss 2003 optical model): light grid -> sweeps that
// carry each light's direct luminance and indirect RGB through the illumination volume ->
// optionally the eye sweep. It keeps the light grid while the volume, material and resolution
// stay, the light sweeps' result while the lights and propagation knobs stay too, and the eye
// sweep's while the camera stays as well.
#pragma once
#include <string>
#include <vector>

#include "illumination_volume.h"
#include "kernel_backend.h"
#include "light_grid.h"
#include "scene.h"
#include "stage_clock.h"

namespace voxlux {

// Bytes the illumination stage needs at light-grid dimensions `dims`: the light grid, the
// luminance, and with indirect light the indirect cells (their own extinction grid when chroma
// subsampled, an input copy for the eye sweep).
size_t illuminationBytes(glm::ivec3 dims, bool indirect, int chroma, bool eye_pass);

class IlluminationStage {
public:
    // Brings the volume up to date for `scene` (camera `camera`, whose volume content `volume_key`
    // identifies) and points `inputs` at it. Appends the passes that ran to `times` and what was
    // kept to `reused`.
    void update(const Scene& scene, const Camera& camera, const std::string& volume_key, KernelInputs& inputs,
                KernelBackend& backend, StageTimes& times, std::vector<std::string>& reused,
                std::vector<std::string>& warnings);

    const IlluminationVolume& volume() const { return volume_; }

private:
    std::string grid_key_;
    LightGrid grid_;
    std::vector<float> chroma_sigma_;   // the light grid averaged over 2^3 cells (chroma subsampling)
    std::string light_key_;             // what the light sweeps were computed from
    std::string eye_key_;               // and the eye sweep ("" = not applied)
    std::vector<float> before_eye_;     // the light sweeps' indirect block, while the eye sweep replaces it
    IlluminationVolume volume_;
};

}  // namespace voxlux
