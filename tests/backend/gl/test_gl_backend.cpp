// The GL backend against the CPU backend on small synthetic volumes (gl_agreement.h): lights and
// ray-marched shadows, emission and colour grids, a transfer function, no lights; and the grade
// shader's compile errors. Each lighting method's own agreement is in tests/lighting/<method>/.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <utility>

#include "backend/backend_choice.h"
#include "scene/camera.h"
#include "gl/gl_context.h"
#include "gl/gl_program.h"
#include "backend/gl/gl_agreement.h"
#include "render/renderer.h"
#include "kernel/shader_source.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

using namespace gl_agreement;

TEST(GlBackend, NameNamesTheRenderer) {
    VOXLUX_REQUIRE_GL(gl);
    EXPECT_EQ(gl->name().rfind("gl (", 0), 0u) << gl->name();
}

TEST(GlBackend, MatchesCpuWithShadowedDirectionalAndPointLights) {
    VOXLUX_REQUIRE_GL(gl);
    const auto stats = expectMatch(renderBoth(makeVolume(false), baseScene(), *gl));
    EXPECT_GT(stats[kDirect].peak, 0.0);
    EXPECT_EQ(stats[kEmission].peak, 0.0);
}

// Unshadowed directional light only: the march takes its telescoped per-batch path.
TEST(GlBackend, MatchesCpuWithUnshadowedDirectionalLight) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.effects.shadows = ShadowMethod::None;
    scene.lights = {directionalLight()};
    EXPECT_GT(expectMatch(renderBoth(makeVolume(false), scene, *gl))[kDirect].peak, 0.0);
}

TEST(GlBackend, MatchesCpuWithEmissionAndColourGrids) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.volume().emission = {emissionSource()};
    const auto stats = expectMatch(renderBoth(makeVolume(true), scene, *gl));
    EXPECT_GT(stats[kDirect].peak, 0.0);
    EXPECT_GT(stats[kEmission].peak, 0.0);
}

// Two sources on grids of different topology: a blackbody from the sphere's grid (its 0..1 up to
// 3000 K) and a ramp from the flame grid.
TEST(GlBackend, MatchesCpuWithTwoEmissionSources) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    EmissionSource fire;
    fire.kind = EmissionKind::Blackbody;
    fire.temperature_scale = 3000.0f;
    fire.cutoff = 600.0f;
    fire.normalization = BlackbodyNormalization::Physical;
    fire.intensity = 2.0f;
    EmissionSource flame;
    flame.kind = EmissionKind::Ramp;
    flame.ramp = {{0.0f, glm::vec3(0.0f)}, {0.5f, {1.0f, 0.3f, 0.05f}}, {1.0f, {1.0f, 0.9f, 0.6f}}};
    flame.intensity = 3.0f;
    scene.volume().emission = {fire, flame};
    LoadedVolume volume = makeVolume(true);
    volume.emission.push_back(flameGrid());
    const auto stats = expectMatch(renderBoth(std::move(volume), scene, *gl));
    EXPECT_GT(stats[kDirect].peak, 0.0);
    EXPECT_GT(stats[kEmission].peak, 0.0);
}

TEST(GlBackend, MatchesCpuWithTransferFunction) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.lights.push_back(spotLight());
    scene.volume().material.transfer = {{0.1f, 0.0f, glm::vec3(1.0f)},
                               {0.5f, 1.5f, glm::vec3(1.0f, 0.6f, 0.3f)},
                               {1.2f, 0.4f, glm::vec3(0.3f, 0.5f, 1.0f)}};
    EXPECT_GT(expectMatch(renderBoth(makeVolume(false), scene, *gl))[kDirect].peak, 0.0);
}

TEST(GlBackend, MatchesCpuWithoutLights) {
    VOXLUX_REQUIRE_GL(gl);
    Scene scene = baseScene();
    scene.lights.clear();
    scene.volume().emission = {emissionSource()};
    const auto stats = expectMatch(renderBoth(makeVolume(true), scene, *gl));
    EXPECT_EQ(stats[kDirect].peak, 0.0);
    EXPECT_EQ(stats[kDirect].max_abs, 0.0);
    EXPECT_GT(stats[kEmission].peak, 0.0);
}

// OCIO's text goes between vx_grade.h and grade.comp; a compile error names the program and
// carries the driver's log.
TEST(GlBackend, GradeShaderErrorsCarryTheLog) {
    VOXLUX_REQUIRE_GL(gl);
    ensureGlContext();
    const GLuint program =
        compileComputeProgram(assembleGradeShader("vec4 ocio_transform(vec4 c) { return c; }"), "grade");
    EXPECT_NE(program, 0u);
    glDeleteProgram(program);
    try {
        compileComputeProgram(assembleGradeShader("vec4 ocio_transform(vec4 c) { return c }"), "broken grade");
        ADD_FAILURE() << "a missing semicolon compiled";
    } catch (const std::runtime_error& e) {
        const std::string message = e.what(), heading = "GL compute shader broken grade does not compile:\n";
        EXPECT_EQ(message.rfind(heading, 0), 0u) << message;
        EXPECT_GT(message.size(), heading.size()) << "no log: " << message;
    }
}

}  // namespace
}  // namespace voxlux::test
