#include "optics/diffusion_profile.h"

#include <cmath>

namespace voxlux {
namespace {

// The diffusion quantities of one channel, in units of the extinction.
struct Diffusion {
    float a, reduced_scattering, reduced_extinction, D, kappa;
};

Diffusion diffusion(float albedo, float g) {
    Diffusion d{};
    d.a = 1.0f - albedo;
    d.reduced_scattering = albedo * (1.0f - g);
    d.reduced_extinction = d.a + d.reduced_scattering;
    d.D = 1.0f / (3.0f * d.reduced_extinction);
    d.kappa = std::sqrt(3.0f * d.a * d.reduced_extinction);
    return d;
}

}  // namespace

FluenceProfile collimatedFluence(glm::vec3 albedo, float g) {
    FluenceProfile p;
    for (int c = 0; c < 3; ++c) {
        const Diffusion d = diffusion(albedo[c], g);
        // Particular solution K exp(-t' tau) with K = 3 alpha (1 - g) / (3 a - t'), and C from the
        // boundary condition C + K = 2 D (-kappa C - t' K). Both diverge where kappa = t', but with
        // 3 a - t' = (kappa - t') (kappa + t') / t' their sum has no singularity:
        // C + K = 2 alpha (1 - g) / ((kappa + t') (1 + 2 D kappa)).
        p.amplitude[c] = 2.0f * d.reduced_scattering / ((d.kappa + d.reduced_extinction) * (1.0f + 2.0f * d.D * d.kappa));
        p.attenuation[c] = d.kappa;
    }
    return p;
}

glm::vec3 diffuseSkyFactor(glm::vec3 albedo, float g) {
    glm::vec3 f;
    for (int c = 0; c < 3; ++c) {
        const Diffusion d = diffusion(albedo[c], g);
        f[c] = 1.0f / (1.0f + 2.0f * d.D * d.kappa);
    }
    return f;
}

}  // namespace voxlux
