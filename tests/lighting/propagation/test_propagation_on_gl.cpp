// Illumination propagation on the GL backend against the CPU (gl_agreement.h): each backend sweeps
// the illumination volume, then marches it, and the AOVs match.
#include "backend/gl/gl_agreement.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

using namespace gl_agreement;

// Propagation shadows with indirect light (Kniss's transport colour, and the diffusion model of a
// coloured albedo), the eye pass, chroma subsampling, perturbation and surface shading: the
// illumination volume is swept by each backend, then marched, and read trilinearly and by the
// B-spline.
TEST(GlBackend, MatchesCpuWithPropagation) {
    VOXLUX_REQUIRE_GL(gl);
    for (IndirectModel model : {IndirectModel::Kniss, IndirectModel::Diffusion}) {
        Scene s = baseScene();
        s.effects.shadows = ShadowMethod::Propagation;
        s.effects.light_resolution = 24;
        Indirect in;
        in.model = model;
        in.transport_color = glm::vec3(1.0f, 0.6f, 0.35f);
        s.volume().material.albedo = glm::vec3(0.95f, 0.8f, 0.6f);
        s.effects.indirect = in;
        s.effects.propagation.eye_pass = true;
        s.effects.propagation.chroma_subsampling = true;
        // Each read of the illumination volume once: the B-spline with the diffusion model.
        s.effects.propagation.filter = model == IndirectModel::Kniss ? Filter::Trilinear : Filter::Tricubic;
        Perturbation p;
        p.density = 0.6f;
        p.transport = 0.3f;
        p.displacement = 1.0f;
        s.effects.perturbation = p;
        s.effects.surface = SurfaceShading{};
        s.lights = {directionalLight(), pointLight(), spotLight()};
        s.volume().emission = {EmissionSource{}};
        const auto stats = expectMatch(renderBoth(makeVolume(true), s, *gl));
        EXPECT_GT(stats[kDirect].peak, 0.0);
        EXPECT_GT(stats[kIndirect].peak, 0.0);
    }
}

// Emission lighting the medium with no light at all: the source sweeps alone fill the indirect
// block (unperturbed, so the CPU runs its row batches and GL the per-cell kernel).
TEST(GlBackend, MatchesCpuWithEmissionLightingTheMedium) {
    VOXLUX_REQUIRE_GL(gl);
    Scene s = baseScene();
    s.lights.clear();
    s.effects.shadows = ShadowMethod::Propagation;
    s.effects.light_resolution = 24;
    s.effects.indirect = Indirect{};
    s.volume().material.albedo = glm::vec3(0.9f, 0.7f, 0.5f);
    s.volume().emission = {emissionSource()};
    const auto stats = expectMatch(renderBoth(makeVolume(true), s, *gl));
    EXPECT_GT(stats[kIndirect].peak, 0.0);
    EXPECT_EQ(stats[kDirect].peak, 0.0);
}

}  // namespace
}  // namespace voxlux::test
