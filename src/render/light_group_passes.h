// Light groups (output.aovs "light_groups") on the march: the beauty split by light, so that a
// compositor balances the key, the fill and the fire's glow without a re-render. The march runs
// once per group over the same samples (the medium, the steps and the early termination do not
// depend on the lights), each pass scattering its group's lights and ambient light alone (and
// reading its group's illumination volume under propagation); with emission, one more pass
// brings the emitted light alone. A layer is its pass's light, and the beauty's colour and light
// AOVs are the layers' sum, so the groups sum to the beauty whatever the method.
// Cost: one march a layer. Shadow rays and a method's per-light work split among the passes, so
// what repeats is the primary march, not the lights.
#pragma once
#include <string>
#include <vector>

#include "kernel/kernel_backend.h"
#include "scene/scene.h"

namespace voxlux {

// Marches `inputs` `passes` times (lightGroupMarches): once per light group (their names in
// `groups`, from lightGroups) and, with one more, for the emitted light: an image whose
// light_groups are the groups' layers and "emission".
RenderImage marchLightGroups(KernelBackend& backend, const KernelInputs& inputs, const std::vector<std::string>& groups, int passes);

// The parameters of the march of layer `layer` of `inputs` (a light group's index, or the number
// of groups for the emitted light's): its group's lights and ambient light, emission only in the
// emitted light's. The Monte Carlo reference splits its paths by the same groups instead.
kernel::VxParams lightGroupParams(const KernelInputs& inputs, int layer, int groups);

}  // namespace voxlux
