// A lighting method added from outside src/lighting/: one stage ("constant_transmittance") whose
// light cache holds one optical depth for every light everywhere, registered by the test alone
// (registerLightingMethod). It proves that a method is a unit: its stage joins the render graph
// with the edges its constructor states, --explain lists it, and the march reads its output
// through MarchLightingStage without naming it. Its kernel is the SAT's light-cache hook: it hands
// the march L.extinction_sat and the "LightCache" array, so it lights scenes whose effects.shadows
// is "sat_cone", after the SAT's.
#include <cmath>

#include "lighting/lighting_method.h"
#include "lighting/march_lighting.h"
#include "kernel/kernel_inputs.h"
#include "scene/scene.h"
#include "render/renderer.h"
#include "test_support.h"
#include "volume/volume_stages.h"

namespace voxlux::test {
namespace {

constexpr float kOpticalDepth = 0.75f;   // every light's, at every point

class ConstantTransmittanceStage final : public MarchLightingStage {
public:
    explicit ConstantTransmittanceStage(const ClassifyStage& classify) { input(classify); }
    std::string name() const override { return "constant_transmittance"; }
    StageReads reads() const override { return {{"/effects/shadows", "/lights/*/type", "/lights/*/enabled"}}; }
    StageActivity activity(const Scene& s) const override {
        if (s.effects.shadows != ShadowMethod::SatCone) return {false, "skipped: shadows are not sat_cone"};
        return {true, "every light's transmittance is exp(-0.75)"};
    }
    void run(StageRun& run) override {
        lights_ = enabledLightCount(run.scene({"/lights/*/type", "/lights/*/enabled"}), false);   // the kernel's packed lights
        // 2^3 cells, the smallest grid the trilinear lookup reads, one channel a light.
        values_.assign(size_t(8 * lights_), kOpticalDepth);
        ++runs;
    }
    void release() override { values_.clear(); }
    void lightTheMarch(const Scene& /* scene */, MarchLighting& lighting) const override {
        if (values_.empty()) return;
        kernel::VxSatMarch& b = lighting.blocks.extinction_sat;
        b = kernel::VxSatMarch{};
        b.world_to_cache = glm::mat4(1.0f);
        b.cache_dims = glm::ivec3(2);
        b.cache_floats = lights_;
        b.shadows = 1;
        lighting.setArray("LightCache", values_.data(), values_.size() * sizeof(float));
    }
    int runs = 0;

private:
    int lights_ = 0;
    std::vector<float> values_;
};

class ConstantTransmittanceMethod final : public LightingMethod {
public:
    explicit ConstantTransmittanceMethod(const SharedStages& shared) : stage_(shared.classify) {}
    std::vector<Stage*> stages() override { return {&stage_}; }
    std::vector<const MarchLightingStage*> marchInputs() const override { return {&stage_}; }

private:
    ConstantTransmittanceStage stage_;
};

// Registered for the test's lifetime, so other tests in the same process never see it.
struct ToyMethodRegistered {
    ToyMethodRegistered() {
        registerLightingMethod({"constant_transmittance",
                                [](const SharedStages& shared) { return std::make_unique<ConstantTransmittanceMethod>(shared); }});
    }
    ~ToyMethodRegistered() { unregisterLightingMethod("constant_transmittance"); }
};

Scene litBall(const std::string& vdb, ShadowMethod shadows) {
    Scene s;
    s.volume().path = vdb;
    s.render.width = 40;
    s.render.height = 32;
    s.render.backend = Backend::Cpu;
    s.volume().material.density_scale = 4.0f;
    s.effects.shadows = shadows;
    Light key;
    key.direction = glm::normalize(glm::vec3(-1, -1, -0.5f));
    key.intensity = 5.0f;
    s.lights = {key};
    return s;
}

TEST(ToyMethod, AMethodFromATestFolderJoinsTheGraphAndLightsTheMarch) {
    const std::string vdb = writeBall(tempDir("toy_method"));
    const FrameResult unshadowed = Renderer(litBall(vdb, ShadowMethod::None)).render(std::nullopt, false);

    const ToyMethodRegistered toy;
    Renderer renderer(litBall(vdb, ShadowMethod::SatCone));
    const std::string plan = renderer.graph().explain(renderer.scene());
    EXPECT_NE(plan.find("run   constant_transmittance every light's transmittance is exp(-0.75)  [after: classify; reads: "
                        "/effects/shadows /lights/*/type /lights/*/enabled]"),
              std::string::npos)
        << plan;
    EXPECT_NE(plan.find("[after: color_space brick classify volumes camera holdouts empty_check light_cache propagation eye_pass constant_transmittance;"),
              std::string::npos)
        << plan;

    // The march reads the toy's cache (the later of the two light caches): every sample's direct
    // light is the unshadowed one times exp(-0.75), so the whole image's is.
    const FrameResult lit = renderer.render(std::nullopt, false);
    ASSERT_EQ(lit.image.pixels.size(), unshadowed.image.pixels.size());
    double sum_lit = 0, sum_unshadowed = 0;
    for (size_t i = 0; i < lit.image.pixels.size(); ++i) {
        sum_lit += luminance(lit.image.pixels[i].direct);
        sum_unshadowed += luminance(unshadowed.image.pixels[i].direct);
        EXPECT_NEAR(lit.image.pixels[i].direct.x, unshadowed.image.pixels[i].direct.x * std::exp(-kOpticalDepth),
                    1e-5 * unshadowed.image.pixels[i].direct.x + 1e-12)
            << "pixel " << i;
    }
    EXPECT_GT(sum_unshadowed, 1.0);
    EXPECT_NEAR(sum_lit / sum_unshadowed, std::exp(-kOpticalDepth), 1e-5);

    // A scene that does not ask for it skips it, and says why.
    renderer.setScene(litBall(vdb, ShadowMethod::Raymarch));
    EXPECT_NE(renderer.graph().explain(renderer.scene()).find("skip  constant_transmittance skipped: shadows are not sat_cone"),
              std::string::npos);
}

TEST(ToyMethod, ANameIsRegisteredOnce) {
    const ToyMethodRegistered toy;
    try {
        registerLightingMethod({"propagation", nullptr});
        FAIL() << "no error";
    } catch (const std::logic_error& e) {
        EXPECT_EQ(std::string(e.what()), "lighting method propagation is registered already");
    }
    std::vector<std::string> names;
    for (const LightingMethodEntry& m : lightingMethods()) names.push_back(m.name);
    EXPECT_EQ(names, (std::vector<std::string>{"extinction_sat", "propagation", "constant_transmittance"}));
}

}  // namespace
}  // namespace voxlux::test
