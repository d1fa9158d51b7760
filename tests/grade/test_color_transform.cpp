// The grade stage's colour transforms (KernelBackend::transformColors): OCIO processors from the
// shared configs and LUT files run through the CPU processor and the generated GLSL, which must
// agree within 1e-4; the CPU against the ASC CDL v1.2 formula; and the premultiplication rules of
// shaders/vx_grade.h on both backends.
#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

#include "backend/backend_choice.h"
#include "grade/color_transformer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {
namespace OCIO = OCIO_NAMESPACE;

struct Case {
    std::string name;
    OCIO::ConstProcessorRcPtr processor;
    float range;  // unpremultiplied colour spans [0, range]: 16 for scene-linear inputs, 1 for display or LUT inputs
};

// Deterministic premultiplied RGBA: every 7th pixel has alpha 0 (alternately black, and coloured
// like emission from a medium too thin to absorb), every 3rd an alpha in [0.05, 1), the rest 1;
// every 11th has an exact 0 in one channel.
std::vector<glm::vec4> testImage(float range) {
    uint32_t state = 12345u;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;  // Numerical Recipes LCG: the same on every platform
        return float(state >> 8) / float(1u << 24);
    };
    std::vector<glm::vec4> pixels(1 << 16);
    for (size_t i = 0; i < pixels.size(); ++i) {
        glm::vec3 c(next() * range, next() * range, next() * range);
        if (i % 11 == 0) c[i % 3] = 0.0f;
        float alpha = 1.0f;
        if (i % 7 == 0)
            alpha = 0.0f;
        else if (i % 3 == 0)
            alpha = 0.05f + 0.95f * next();
        if (i % 14 == 0) c = glm::vec3(0.0f);
        pixels[i] = glm::vec4(alpha > 0.0f ? c * alpha : c, alpha);
    }
    return pixels;
}

// Largest |gl - cpu| over the colour channels, relative where |cpu| > 1; alpha must be untouched,
// and the transform must change the image (else agreeing proves nothing).
double backendDifference(const Case& c, KernelBackend& gl) {
    const std::vector<glm::vec4> input = testImage(c.range);
    std::vector<glm::vec4> on_cpu = input, on_gl = input;
    makeColorTransformer(Device::Cpu)->transformColors(c.processor, on_cpu, true);
    makeColorTransformer(gl.device())->transformColors(c.processor, on_gl, true);
    EXPECT_NE(std::memcmp(on_cpu.data(), input.data(), input.size() * sizeof(glm::vec4)), 0) << c.name;
    double worst = 0.0;
    for (size_t i = 0; i < input.size(); ++i) {
        EXPECT_EQ(on_cpu[i].w, input[i].w) << c.name << ", cpu pixel " << i;
        EXPECT_EQ(on_gl[i].w, input[i].w) << c.name << ", gl pixel " << i;
        for (int k = 0; k < 3; ++k) {
            const double a = on_cpu[i][k], b = on_gl[i][k];
            double e = std::abs(b - a) / std::max(1.0, std::abs(a));
            if (std::isnan(a) != std::isnan(b)) e = std::numeric_limits<double>::infinity();
            if (!std::isnan(e)) worst = std::max(worst, e);
        }
    }
    return worst;
}

void expectBackendsAgree(const std::vector<Case>& cases, KernelBackend& gl) {
    for (const Case& c : cases) {
        ASSERT_FALSE(c.processor->isNoOp()) << c.name;
        const double difference = backendDifference(c, gl);
        std::printf("  %-52s max |gl - cpu| %.2g\n", c.name.c_str(), difference);
        EXPECT_LE(difference, 1e-4) << c.name;
    }
}

// The cpu backend, and the gl one unless VOXLUX_SKIP_GL=1.
std::vector<std::unique_ptr<KernelBackend>> bothBackends() {
    std::vector<std::unique_ptr<KernelBackend>> out;
    out.push_back(makeCpuBackend());
    if (auto gl = glBackendOrSkip()) out.push_back(std::move(gl));
    return out;
}

OCIO::ConstProcessorRcPtr fileProcessor(const std::string& path, OCIO::Interpolation interpolation,
                                        const char* cccid = "") {
    OCIO::FileTransformRcPtr file = OCIO::FileTransform::Create();
    file->setSrc(path.c_str());
    file->setCCCId(cccid);
    file->setInterpolation(interpolation);
    return OCIO::Config::CreateRaw()->getProcessor(file);
}

TEST(ColorTransform, AcesConfigAgreesOnBothBackends) {
    VOXLUX_REQUIRE_SHARED(path, "ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio");
    VOXLUX_REQUIRE_GL(gl);
    const OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
    OCIO::DisplayViewTransformRcPtr display = OCIO::DisplayViewTransform::Create();
    display->setSrc("ACEScg");
    display->setDisplay("sRGB - Display");
    display->setView("ACES 1.0 - SDR Video");
    OCIO::LookTransformRcPtr look = OCIO::LookTransform::Create();
    look->setSrc("ACEScg");
    look->setDst("ACEScg");
    look->setLooks("ACES 1.3 Reference Gamut Compression");
    expectBackendsAgree({{"ACEScg -> ACES2065-1", config->getProcessor("ACEScg", "ACES2065-1"), 16.0f},
                         {"ACEScg -> ACEScct", config->getProcessor("ACEScg", "ACEScct"), 16.0f},
                         {"ACEScg -> sRGB - Display / ACES 1.0 - SDR Video", config->getProcessor(display), 16.0f},
                         {"ACEScg, look ACES 1.3 Reference Gamut Compression", config->getProcessor(look), 16.0f}},
                        *gl);
}

TEST(ColorTransform, GradingFilesAgreeOnBothBackends) {
    VOXLUX_REQUIRE_SHARED(dir, "ocio/grading_test_files");
    VOXLUX_REQUIRE_GL(gl);
    std::vector<Case> cases = {
        {"cdl_test1.cc", fileProcessor(dir + "/cdl_test1.cc", OCIO::INTERP_DEFAULT), 1.0f},
        {"cdl_test1.ccc, cc0002", fileProcessor(dir + "/cdl_test1.ccc", OCIO::INTERP_DEFAULT, "cc0002"), 1.0f},
        {"cdl_test1.cdl, cc0003", fileProcessor(dir + "/cdl_test1.cdl", OCIO::INTERP_DEFAULT, "cc0003"), 1.0f},
        {"cdl_all_styles.clf", fileProcessor(dir + "/cdl_all_styles.clf", OCIO::INTERP_DEFAULT), 1.0f},
        {"iridas_1d.cube, linear", fileProcessor(dir + "/iridas_1d.cube", OCIO::INTERP_LINEAR), 1.0f},
    };
    for (const char* lut : {"lut3d_1.spi3d", "iridas_3d.cube", "resolve_1d3d.cube", "lut3d_17x17x17_10i_12i.clf"}) {
        const std::string path = dir + "/" + lut;
        cases.push_back({std::string(lut) + ", tetrahedral", fileProcessor(path, OCIO::INTERP_TETRAHEDRAL), 1.0f});
        cases.push_back({std::string(lut) + ", linear", fileProcessor(path, OCIO::INTERP_LINEAR), 1.0f});
    }
    expectBackendsAgree(cases, *gl);
}

// A profile-1 config whose spaces are file LUTs: lm16's 131072-entry 1D LUT is a 2D texture on the GPU.
TEST(ColorTransform, SpiAnimConfigAgreesOnBothBackends) {
    VOXLUX_REQUIRE_SHARED(path, "ocio/spi-anim/config.ocio");
    VOXLUX_REQUIRE_GL(gl);
    const OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
    expectBackendsAgree({{"spi-anim lm16 -> lnf", config->getProcessor("lm16", "lnf"), 1.0f},
                         {"spi-anim lnf -> p3dci8", config->getProcessor("lnf", "p3dci8"), 16.0f}},
                        *gl);
}

// Dynamic properties are uniforms, which the processor's cache ID leaves out: two exposures under
// one ID must each come through.
TEST(ColorTransform, DynamicPropertiesAgreeOnBothBackends) {
    VOXLUX_REQUIRE_GL(gl);
    const OCIO::ConstConfigRcPtr raw = OCIO::Config::CreateRaw();
    // A config per processor: a config's processor cache, keyed like the cache ID, would return
    // the first exposure for the second.
    auto exposure = [](double stops) {
        OCIO::ExposureContrastTransformRcPtr t = OCIO::ExposureContrastTransform::Create();
        t->setExposure(stops);
        t->setContrast(1.2);
        t->setPivot(0.18);
        t->makeExposureDynamic();
        t->makeContrastDynamic();
        return OCIO::Config::CreateRaw()->getProcessor(t);
    };
    const OCIO::ConstProcessorRcPtr brighter = exposure(0.5), darker = exposure(-1.5);
    ASSERT_STREQ(brighter->getCacheID(), darker->getCacheID());
    std::vector<glm::vec4> bright = testImage(16.0f), dark = bright;
    makeColorTransformer(Device::Cpu)->transformColors(brighter, bright, true);
    makeColorTransformer(Device::Cpu)->transformColors(darker, dark, true);
    ASSERT_NE(std::memcmp(bright.data(), dark.data(), bright.size() * sizeof(glm::vec4)), 0);

    OCIO::GradingPrimaryTransformRcPtr primary = OCIO::GradingPrimaryTransform::Create(OCIO::GRADING_LIN);
    OCIO::GradingPrimary values(OCIO::GRADING_LIN);
    values.m_offset = OCIO::GradingRGBM(0.01, 0.02, -0.01, 0.0);
    values.m_exposure = OCIO::GradingRGBM(0.2, 0.0, -0.3, 0.1);
    values.m_saturation = 1.3;
    primary->setValue(values);
    primary->makeDynamic();

    OCIO::GradingRGBCurveTransformRcPtr curve = OCIO::GradingRGBCurveTransform::Create(OCIO::GRADING_LOG);
    const OCIO::ConstGradingBSplineCurveRcPtr s_curve =
        OCIO::GradingBSplineCurve::Create({{0.0f, 0.0f}, {0.3f, 0.25f}, {0.7f, 0.8f}, {1.0f, 1.0f}});
    const OCIO::ConstGradingBSplineCurveRcPtr identity =
        OCIO::GradingBSplineCurve::Create({{0.0f, 0.0f}, {1.0f, 1.0f}});
    curve->setValue(OCIO::GradingRGBCurve::Create(s_curve, identity, s_curve, identity));
    curve->makeDynamic();

    expectBackendsAgree({{"exposure +0.5, contrast 1.2 (dynamic)", brighter, 16.0f},
                         {"exposure -1.5, contrast 1.2 (dynamic, same cache ID)", darker, 16.0f},
                         {"grading primary, linear (dynamic)", raw->getProcessor(primary), 16.0f},
                         {"grading RGB curves, log (dynamic)", raw->getProcessor(curve), 1.0f}},
                        *gl);
}

// ASC CDL v1.2 (the CDL_ASC style): out = clamp(luma + sat (sop - luma)), with
// sop = clamp(in slope + offset)^power, luma with Rec.709 weights, clamps to [0, 1].
glm::dvec3 ascCdl(glm::dvec3 in, glm::dvec3 slope, glm::dvec3 offset, glm::dvec3 power, double sat) {
    const glm::dvec3 sop = glm::pow(glm::clamp(in * slope + offset, 0.0, 1.0), power);
    const double luma = glm::dot(sop, glm::dvec3(0.2126, 0.7152, 0.0722));
    return glm::clamp(luma + sat * (sop - luma), 0.0, 1.0);
}

TEST(ColorTransform, CdlMatchesTheAscFormula) {
    const glm::dvec3 slope(1.2, 1.0, 0.8), offset(0.02, -0.01, 0.05), power(1.1, 0.9, 1.25);
    const double sat = 0.8;
    OCIO::CDLTransformRcPtr cdl = OCIO::CDLTransform::Create();
    cdl->setStyle(OCIO::CDL_ASC);
    cdl->setSlope(&slope.x);
    cdl->setOffset(&offset.x);
    cdl->setPower(&power.x);
    cdl->setSat(sat);
    const OCIO::ConstProcessorRcPtr processor = OCIO::Config::CreateRaw()->getProcessor(cdl);
    // Mid grey, a saturated colour, one clamped above by slope + offset, one below by the offset.
    const std::vector<glm::vec4> input = {
        {0.18f, 0.18f, 0.18f, 1.0f}, {0.5f, 0.25f, 0.75f, 1.0f}, {0.9f, 0.95f, 0.1f, 1.0f}, {0.3f, 0.0f, 0.6f, 1.0f}};
    std::vector<glm::vec4> pixels = input;
    makeColorTransformer(Device::Cpu)->transformColors(processor, pixels, true);
    for (size_t i = 0; i < input.size(); ++i) {
        const glm::dvec3 expected = ascCdl(glm::dvec3(input[i]), slope, offset, power, sat);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(pixels[i][k], expected[k], 2e-6) << "pixel " << i << " channel " << k;
        EXPECT_EQ(pixels[i].w, 1.0f);
    }
    // The first pixel by hand: sop = (0.236^1.1, 0.17^0.9, 0.194^1.25) = (0.2043, 0.2030, 0.1288),
    // luma 0.1979, out = luma + 0.8 (sop - luma).
    EXPECT_NEAR(pixels[0].x, 0.2030, 1e-4);
    EXPECT_NEAR(pixels[0].y, 0.2019, 1e-4);
    EXPECT_NEAR(pixels[0].z, 0.1426, 1e-4);
}

// vx_grade.h under out = 1.5 in + 0.1 (a CDL offset lifts black): background stays black,
// partial alpha is unpremultiplied and premultiplied back, colour at alpha 0 (thin emission) is
// transformed as it is, alpha never changes.
TEST(ColorTransform, PremultipliedAlphaRules) {
    OCIO::CDLTransformRcPtr cdl = OCIO::CDLTransform::Create();
    cdl->setStyle(OCIO::CDL_NO_CLAMP);
    const double slope[3] = {1.5, 1.5, 1.5}, offset[3] = {0.1, 0.1, 0.1};
    cdl->setSlope(slope);
    cdl->setOffset(offset);
    const OCIO::ConstProcessorRcPtr processor = OCIO::Config::CreateRaw()->getProcessor(cdl);
    const std::vector<glm::vec4> input = {
        {0.0f, 0.0f, 0.0f, 0.0f}, {0.2f, 0.1f, 0.3f, 0.5f}, {0.2f, 0.1f, 0.3f, 0.0f}, {0.2f, 0.1f, 0.3f, 1.0f}};
    const std::vector<glm::vec4> unpremultiplied = {
        {0.0f, 0.0f, 0.0f, 0.0f}, {0.35f, 0.2f, 0.5f, 0.5f}, {0.4f, 0.25f, 0.55f, 0.0f}, {0.4f, 0.25f, 0.55f, 1.0f}};
    const std::vector<glm::vec4> straight = {
        {0.1f, 0.1f, 0.1f, 0.0f}, {0.4f, 0.25f, 0.55f, 0.5f}, {0.4f, 0.25f, 0.55f, 0.0f}, {0.4f, 0.25f, 0.55f, 1.0f}};
    for (const auto& backend : bothBackends())
        for (bool unpremultiply : {true, false}) {
            std::vector<glm::vec4> pixels = input;
            makeColorTransformer(backend->device())->transformColors(processor, pixels, unpremultiply);
            const std::vector<glm::vec4>& expected = unpremultiply ? unpremultiplied : straight;
            for (size_t i = 0; i < input.size(); ++i)
                for (int k = 0; k < 4; ++k)
                    EXPECT_NEAR(pixels[i][k], expected[i][k], 1e-6)
                        << backend->name() << (unpremultiply ? ", unpremultiplied" : "") << ", pixel " << i
                        << " channel " << k;
        }
}

// Images longer than the GL backend's block of 1 << 20 pixels run in several dispatches, the
// last one partial: every pixel must still come back in its place.
TEST(ColorTransform, LargeImagesRunInBlocks) {
    VOXLUX_REQUIRE_GL(gl);
    OCIO::CDLTransformRcPtr cdl = OCIO::CDLTransform::Create();
    const double slope[3] = {1.5, 0.5, 2.0}, offset[3] = {0.1, 0.2, -0.1};
    cdl->setSlope(slope);
    cdl->setOffset(offset);
    const OCIO::ConstProcessorRcPtr processor = OCIO::Config::CreateRaw()->getProcessor(cdl);
    std::vector<glm::vec4> pixels((size_t(1) << 21) + 1000);  // two whole blocks and a partial one
    auto input = [](size_t i) { return glm::vec3(float(i) * 1e-6f, float(i % 1000) * 1e-3f, 0.5f); };
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = glm::vec4(input(i), 1.0f);
    makeColorTransformer(gl->device())->transformColors(processor, pixels, true);
    size_t misplaced = 0;
    for (size_t i = 0; i < pixels.size(); ++i) {
        const glm::vec3 expected = glm::vec3(1.5f, 0.5f, 2.0f) * input(i) + glm::vec3(0.1f, 0.2f, -0.1f);
        misplaced += glm::any(glm::greaterThan(glm::abs(glm::vec3(pixels[i]) - expected), glm::vec3(1e-5f)));
    }
    EXPECT_EQ(misplaced, 0u) << "of " << pixels.size() << " pixels";
}

// A no-op processor returns at once: not even the unpremultiply round trip touches the pixels.
TEST(ColorTransform, NoOpLeavesPixelsUntouched) {
    const OCIO::ConstProcessorRcPtr processor = OCIO::Config::CreateRaw()->getProcessor("raw", "raw");
    ASSERT_TRUE(processor->isNoOp());
    const std::vector<glm::vec4> input = {
        {0.3f, 0.7f, 0.1f, 0.3f}, {std::nanf(""), 1.0f, 2.0f, 0.0f}, {1e-30f, 5.0f, 0.0f, 0.7f}};
    for (const auto& backend : bothBackends()) {
        std::vector<glm::vec4> pixels = input;
        makeColorTransformer(backend->device())->transformColors(processor, pixels, true);
        EXPECT_EQ(std::memcmp(pixels.data(), input.data(), input.size() * sizeof(glm::vec4)), 0) << backend->name();
    }
}

}  // namespace
}  // namespace voxlux::test
