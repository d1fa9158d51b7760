// The environment the camera sees (an environment light's visible_to_camera): behind the volumes,
// each pixel gains the map's radiance along its central ray (filtered bilinearly) times what the volumes leave of it
// (1 - alpha, as a compositor's `over` a background plate: a matte holds it out too), and its alpha
// becomes 1. Where a holdout stops the ray the CG hides the background, so the pixel is left as it
// is. The light's group layer takes the same light, so the groups still sum to the beauty. The
// beauty only: the AOVs and the deep samples hold the volumes alone. Costs one lookup a pixel.
#pragma once
#include "kernel/kernel_backend.h"
#include "kernel/kernel_inputs.h"

namespace voxlux {

// Whether any environment of `inputs` is visible to the camera.
bool seesEnvironment(const KernelInputs& inputs);

void addEnvironmentBackground(const KernelInputs& inputs, RenderImage& image);

}  // namespace voxlux
