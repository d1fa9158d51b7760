// Multiple scattering from diffusion theory: how much light a medium of single-scattering albedo
// alpha and Henyey-Greenstein anisotropy g carries below its surface once it has scattered, as a
// function of the optical depth tau towards the light (extinction units, so the profile fits any
// density). It is what the propagation method's indirect light carries by default
// (effects.indirect.model "diffusion"), in place of Kniss 2003's hand-set transport colour and
// strength. Costs nothing per cell: a few numbers per material, evaluated once per render.
//
// The model is the diffusion approximation with the similarity relation sigma_s' = sigma_s (1 - g)
// (Ishimaru 1978; the dipole literature, e.g. Jensen et al. 2001, uses the same quantities), in
// units of the extinction sigma_t: absorption a = 1 - alpha, reduced extinction t' = 1 - alpha g,
// diffusion coefficient D = 1 / (3 t'), effective attenuation kappa = sqrt(3 a t').
// - Collimated light of irradiance E entering a half-space: the diffuse fluence solves
//   D phi'' - a phi = -alpha (1 - g) E exp(-t' tau) with the partial-current boundary condition
//   phi(0) = 2 D phi'(0), which gives phi = E (C exp(-kappa tau) + K exp(-t' tau)). The indirect
//   sweep carries one exponential: the boundary value C + K = 2 alpha (1 - g) / ((kappa + t')
//   (1 + 2 D kappa)), attenuated at the asymptotic rate kappa. (The full two-term profile builds
//   up below the surface, to about 2 E in a cloud, and deep inside stays C / (C + K), 3.8-7 times,
//   above the one-term form: light a finite cloud loses through its sides. Against the Monte
//   Carlo reference it is 1.6x too bright on the smoke and the cloud of docs/accuracy.md, and the
//   one-term form is not.)
// - Diffuse (sky) light of radiance L: the same boundary condition with an inward current pi L
//   gives phi(0) = 4 pi L / (1 + 2 D kappa), so a surface cell scatters the sky's radiance times
//   alpha / (1 + 2 D kappa) rather than alpha.
// At alpha = 1 the sky factor is 1: a white furnace stays at the ambient radiance. Albedo is per
// colour channel, so every quantity is an RGB triple.
#pragma once
#include <glm/glm.hpp>

namespace voxlux {

// The indirect light's profile per unit irradiance entering the medium, per colour channel:
// amplitude * exp(-attenuation * tau).
struct FluenceProfile {
    glm::vec3 amplitude{1.0f};
    glm::vec3 attenuation{1.0f};
};

// The diffuse fluence below a surface lit by collimated light: C + K and kappa above.
FluenceProfile collimatedFluence(glm::vec3 albedo, float g);

// The share of a uniform sky's radiance that the surface of a half-space scatters per unit albedo:
// 1 / (1 + 2 D kappa), in (0, 1], 1 at albedo 1.
glm::vec3 diffuseSkyFactor(glm::vec3 albedo, float g);

}  // namespace voxlux
