// Colour management: the built-in config, $OCIO and scene configs, spaces, looks, CDLs and their
// errors, checked against hand-computed values, the ASWF configs and OCIO's own ocioconvert.
#include <cmath>
#include <cstdlib>
#include <functional>
#include <random>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfOutputFile.h>

#include "grade/color_pipeline.h"
#include "core/error.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// Runs a scene's colour settings with no $OCIO, so the built-in config is the default.
ColorPipeline pipelineOf(const ColorSettings& color, bool preview = false) {
    ::unsetenv("OCIO");
    return buildColorPipeline(color, preview);
}

std::string errorOf(const ColorSettings& color) {
    try {
        pipelineOf(color);
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

GradeStep lookStep(const std::string& looks) {
    GradeStep g;
    g.kind = GradeKind::Look;
    g.look = looks;
    return g;
}

GradeStep fileStep(GradeKind kind, const std::string& file, const std::string& cccid = "") {
    GradeStep g;
    g.kind = kind;
    g.file = file;
    g.cccid = cccid;
    return g;
}

// Largest relative difference of `ours` from `expected` over the channels (absolute below 1).
float relativeError(glm::vec3 ours, glm::vec3 expected) {
    glm::vec3 e = glm::abs(ours - expected) / glm::max(glm::vec3(1.0f), glm::abs(expected));
    return std::max({e.x, e.y, e.z});
}

glm::vec3 applyRgb(const OCIO::ConstProcessorRcPtr& p, glm::vec3 rgb) {
    float px[3] = {rgb.x, rgb.y, rgb.z};
    p->getDefaultCPUProcessor()->applyRGB(px);
    return {px[0], px[1], px[2]};
}

void expectNear(glm::vec3 a, glm::vec3 b, float tolerance, const std::string& what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tolerance * std::max(1.0f, std::abs(b[c]))) << what << " channel " << c;
}

// ASC CDL v1.2 without clamping, Rec.709 luma for saturation.
glm::vec3 cdl(glm::vec3 in, glm::vec3 slope, glm::vec3 offset, glm::vec3 power, float sat) {
    glm::vec3 out = in * slope + offset;
    for (int c = 0; c < 3; ++c) out[c] = out[c] > 0.0f ? std::pow(out[c], power[c]) : out[c];
    const float luma = 0.2126f * out.x + 0.7152f * out.y + 0.0722f * out.z;
    return glm::vec3(luma) + sat * (out - glm::vec3(luma));
}

// ACEScct encoding of one ACEScg channel (S-2016-001), and back.
float toAcescct(float lin) {
    return lin <= 0.0078125f ? 10.5402377416545f * lin + 0.0729055341958355f : (std::log2(lin) + 9.72f) / 17.52f;
}
float fromAcescct(float cct) {
    return cct <= 0.155251141552511f ? (cct - 0.0729055341958355f) / 10.5402377416545f : std::exp2(cct * 17.52f - 9.72f);
}

std::vector<glm::vec3> hdrColours() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec3> out{glm::vec3(0.0f), glm::vec3(1.0f), glm::vec3(0.18f), glm::vec3(16.0f, 0.5f, 0.01f)};
    for (int i = 0; i < 200; ++i) out.push_back(glm::vec3(u(rng), u(rng), u(rng)) * (u(rng) * 16.0f));
    return out;
}

TEST(Color, BuiltinConfigWorksInAcescgAndWritesItsChromaticities) {
    ColorPipeline p = pipelineOf({});
    EXPECT_EQ(p.config_source, "voxlux built-in config (ocio/voxlux.ocio)");
    EXPECT_EQ(p.working_space, "ACEScg");
    EXPECT_EQ(p.output_space, "ACEScg");
    EXPECT_TRUE(p.grade->isNoOp());
    EXPECT_TRUE(p.output->isNoOp());
    EXPECT_FALSE(p.preview);
    // AP1 primaries and the ACES white (S-2014-004).
    ASSERT_TRUE(p.output_chromaticities);
    const Chromaticities& c = *p.output_chromaticities;
    EXPECT_NEAR(c.red.x, 0.713f, 1e-4f);
    EXPECT_NEAR(c.red.y, 0.293f, 1e-4f);
    EXPECT_NEAR(c.green.x, 0.165f, 1e-4f);
    EXPECT_NEAR(c.green.y, 0.830f, 1e-4f);
    EXPECT_NEAR(c.blue.x, 0.128f, 1e-4f);
    EXPECT_NEAR(c.blue.y, 0.044f, 1e-4f);
    EXPECT_NEAR(c.white.x, 0.32168f, 1e-4f);
    EXPECT_NEAR(c.white.y, 0.33767f, 1e-4f);
    // D65 white in XYZ is white in ACEScg (the config adapts D65 to the ACES white).
    ASSERT_TRUE(p.xyz_to_working);
    expectNear(*p.xyz_to_working * glm::vec3(0.95047f, 1.0f, 1.08883f), glm::vec3(1.0f), 1e-3f, "D65 white");
}

TEST(Color, Aces2065OutputHasAp0Chromaticities) {
    ColorSettings s;
    s.output_space = "ACES2065-1";
    ColorPipeline p = pipelineOf(s);
    ASSERT_TRUE(p.output_chromaticities);
    EXPECT_NEAR(p.output_chromaticities->red.x, 0.7347f, 1e-4f);
    EXPECT_NEAR(p.output_chromaticities->green.y, 1.0f, 1e-4f);
    EXPECT_NEAR(p.output_chromaticities->blue.y, -0.0770f, 1e-4f);
    // A log space has no chromaticities attribute.
    s.output_space = "ACEScct";
    EXPECT_FALSE(pipelineOf(s).output_chromaticities);
}

TEST(Color, WorkingToOutputAndBackIsTheIdentity) {
    for (const std::string space : {"ACES2065-1", "ACEScct", "lin_rec709", "sRGB - Texture"}) {
        ColorSettings there, back;
        there.output_space = space;
        back.working_space = space;
        back.output_space = "ACEScg";
        ColorPipeline to = pipelineOf(there), from = pipelineOf(back);
        float worst = 0.0f;
        for (glm::vec3 c : hdrColours()) {
            if (space == "sRGB - Texture") c = glm::min(c, glm::vec3(1.0f));  // an encoding for [0, 1]
            glm::vec3 round = applyRgb(from.output, applyRgb(to.output, c));
            worst = std::max(worst, relativeError(round, c));
        }
        std::printf("ACEScg -> %s -> ACEScg: worst relative error %.2g\n", space.c_str(), double(worst));
        EXPECT_LE(worst, 1e-5f) << space;
    }
}

TEST(Color, CdlMatchesTheAscFormula) {
    GradeStep step;
    step.kind = GradeKind::Cdl;
    step.slope = {1.2f, 1.0f, 0.8f};
    step.offset = {0.01f, 0.0f, -0.02f};
    step.power = {1.1f, 1.0f, 0.9f};
    step.saturation = 0.8f;
    ColorSettings s;
    s.grade = {step};
    ColorPipeline p = pipelineOf(s);
    for (glm::vec3 in : {glm::vec3(0.18f), glm::vec3(0.5f, 0.25f, 0.1f), glm::vec3(4.0f, 2.0f, 1.0f), glm::vec3(0.0f)})
        expectNear(applyRgb(p.grade, in), cdl(in, step.slope, step.offset, step.power, step.saturation), 1e-5f, "CDL");
    // By hand for one pixel: 0.5 * 1.2 + 0.01 = 0.61, 0.61^1.1 = 0.58056; 0.25; 0.1 * 0.8 - 0.02 = 0.06, 0.06^0.9 = 0.07950;
    // luma 0.2126 * 0.58056 + 0.7152 * 0.25 + 0.0722 * 0.07950 = 0.30818; red 0.30818 + 0.8 * (0.58056 - 0.30818).
    EXPECT_NEAR(applyRgb(p.grade, {0.5f, 0.25f, 0.1f}).x, 0.52608f, 1e-4f);
}

TEST(Color, CdlInItsOwnSpaceAndLookByName) {
    // The built-in "Warm" look is a CDL in ACEScct: encode, grade, decode (ACEScg and ACEScct share AP1).
    ColorSettings look;
    look.grade = {lookStep("Warm")};
    GradeStep cct;
    cct.slope = {1.06f, 1.0f, 0.92f};
    cct.offset = {0.01f, 0.0f, -0.01f};
    cct.saturation = 1.1f;
    cct.space = "ACEScct";
    ColorSettings inline_cdl;
    inline_cdl.grade = {cct};
    ColorPipeline a = pipelineOf(look), b = pipelineOf(inline_cdl);
    for (glm::vec3 in : {glm::vec3(0.18f), glm::vec3(0.9f, 0.4f, 0.05f), glm::vec3(6.0f, 3.0f, 2.0f)}) {
        glm::vec3 enc(toAcescct(in.x), toAcescct(in.y), toAcescct(in.z));
        glm::vec3 graded = cdl(enc, cct.slope, cct.offset, cct.power, cct.saturation);
        glm::vec3 expected(fromAcescct(graded.x), fromAcescct(graded.y), fromAcescct(graded.z));
        expectNear(applyRgb(a.grade, in), expected, 1e-4f, "look Warm");
        expectNear(applyRgb(b.grade, in), expected, 1e-4f, "CDL in ACEScct");
    }
}

TEST(Color, MissingNamesSayWhatExists) {
    ColorSettings s;
    s.output_space = "ACEScgg";
    EXPECT_EQ(errorOf(s),
              "color.output_space: no colour space 'ACEScgg' in voxlux built-in config (ocio/voxlux.ocio) (it has: "
              "CIE-XYZ-D65, sRGB - Display, Rec.1886 Rec.709 - Display, ACES2065-1, ACEScg, ACEScct, "
              "Linear Rec.709 (sRGB), sRGB - Texture, Raw)");
    s = {};
    s.grade = {lookStep("Warm, +Cold")};
    EXPECT_EQ(errorOf(s), "color.grade[0].look: no look 'Cold' in voxlux built-in config (ocio/voxlux.ocio) (it has: "
                          "ACES 1.3 Reference Gamut Compression, Warm)");
    s = {};
    s.display = "P3";
    EXPECT_EQ(errorOf(s), "color.display: no display 'P3' in voxlux built-in config (ocio/voxlux.ocio) (it has: "
                          "sRGB - Display, Rec.1886 Rec.709 - Display)");
    s = {};
    s.view = "Filmic";
    EXPECT_EQ(errorOf(s), "color.view: display 'sRGB - Display' of voxlux built-in config (ocio/voxlux.ocio) has no "
                          "view 'Filmic' (it has: ACES 1.0 - SDR Video, Un-tone-mapped, Raw)");
    s = {};
    s.grade = {fileStep(GradeKind::Lut, "/nowhere/grade.cube")};
    EXPECT_EQ(errorOf(s), "color.grade[0].file: /nowhere/grade.cube: no such file");
    s = {};
    s.config = "/nowhere/config.ocio";
    EXPECT_EQ(errorOf(s), "/nowhere/config.ocio: no such OCIO config (color.config)");
}

TEST(Color, PreviewDefaultsToTheConfigsDisplayAndView) {
    ColorPipeline p = pipelineOf({}, true);
    EXPECT_EQ(p.display, "sRGB - Display");
    EXPECT_EQ(p.view, "ACES 1.0 - SDR Video");
    ASSERT_TRUE(p.preview);
    // The ACES SDR view maps scene-linear mid grey to about 0.39 of the sRGB-encoded range, and black to black.
    glm::vec3 grey = applyRgb(p.preview, glm::vec3(0.18f));
    EXPECT_NEAR(grey.x, grey.y, 1e-3f);
    EXPECT_GT(grey.x, 0.3f);
    EXPECT_LT(grey.x, 0.5f);
    expectNear(applyRgb(p.preview, glm::vec3(0.0f)), glm::vec3(0.0f), 1e-3f, "black");
}

TEST(Color, OcioEnvironmentVariableIsHonoured) {
    VOXLUX_REQUIRE_SHARED(config, "ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio");
    ::setenv("OCIO", config.c_str(), 1);
    ColorPipeline p = buildColorPipeline({}, false);
    ::unsetenv("OCIO");
    EXPECT_EQ(p.config_source, config);
    EXPECT_EQ(p.working_space, "ACEScg");  // its scene_linear role
    ColorSettings scene;
    scene.config = config;
    scene.output_space = "lin_rec709";  // an alias in that config
    EXPECT_EQ(pipelineOf(scene).output_space, "Linear Rec.709 (sRGB)");
}

// Every display/view pair the ASWF configs name builds and gives finite colour.
TEST(Color, AswfConfigsLoadWithAllTheirViews) {
    for (const std::string name : {"ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio", "ocio/studio-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio"}) {
        const std::string config = sharedData(name);
        if (config.empty()) GTEST_SKIP() << "../shared/data/" << name << " is absent (fresh clone): skipped";
        ColorSettings s;
        s.config = config;
        ColorPipeline base = pipelineOf(s);
        EXPECT_EQ(base.working_space, "ACEScg") << name;
        int pairs = 0;
        for (int d = 0; d < base.config->getNumDisplays(); ++d) {
            s.display = base.config->getDisplay(d);
            for (int v = 0; v < base.config->getNumViews(s.display.c_str()); ++v) {
                s.view = base.config->getView(s.display.c_str(), v);
                ColorPipeline p = pipelineOf(s);
                glm::vec3 out = applyRgb(p.preview, glm::vec3(0.18f, 2.0f, 0.01f));
                EXPECT_TRUE(std::isfinite(out.x) && std::isfinite(out.y) && std::isfinite(out.z)) << s.display << " / " << s.view;
                ++pairs;
            }
        }
        std::printf("%s: %d display/view pairs\n", name.c_str(), pairs);
        EXPECT_GE(pairs, 10) << name;
    }
}

TEST(Color, ProfileOneConfigWithFileLuts) {
    VOXLUX_REQUIRE_SHARED(config, "ocio/spi-anim/config.ocio");
    ColorSettings s;
    s.config = config;
    ColorPipeline p = pipelineOf(s);
    EXPECT_FALSE(p.working_space.empty());
    s.output_space = "vd8";  // an 8-bit video space through .spi1d LUTs
    glm::vec3 out = applyRgb(pipelineOf(s).output, glm::vec3(0.18f));
    EXPECT_GT(out.x, 0.0f);
    EXPECT_LT(out.x, 1.0f);
}

TEST(Color, CdlFilesLoadByCccid) {
    VOXLUX_REQUIRE_SHARED(ccc, "ocio/grading_test_files/cdl_test1.ccc");
    ColorSettings s;
    s.grade = {fileStep(GradeKind::CdlFile, ccc, "cc0003")};
    EXPECT_NO_THROW(pipelineOf(s));
    s.grade[0].cccid = "no-such-id";
    const std::string error = errorOf(s);
    EXPECT_EQ(error.rfind("color.grade[0]: ", 0), 0u) << error;
    EXPECT_NE(error.find("no-such-id"), std::string::npos) << error;
}

// A one-row float RGBA EXR of `colours` (alpha 1), as ocioconvert's input.
void writeFloatRow(const std::string& path, const std::vector<glm::vec3>& colours) {
    const int n = int(colours.size());
    std::vector<float> planes[4];
    for (const auto& c : colours)
        for (int k = 0; k < 4; ++k) planes[k].push_back(k < 3 ? c[k] : 1.0f);
    Imf::Header header(n, 1);
    Imf::FrameBuffer fb;
    const char* names[] = {"R", "G", "B", "A"};
    for (int k = 0; k < 4; ++k) {
        header.channels().insert(names[k], Imf::Channel(Imf::FLOAT));
        fb.insert(names[k], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[k].data()), sizeof(float), sizeof(float) * n));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(1);
}

// Runs ocioconvert under voxlux's config and compares each pixel with `expected(colour)`.
void expectOcioconvertMatches(const std::string& arguments, const std::vector<glm::vec3>& colours,
                              const std::function<glm::vec3(glm::vec3)>& expected) {
    const std::string dir = tempDir("ocioconvert");
    writeFloatRow(dir + "/in.exr", colours);
    std::string command = arguments;
    for (const std::string name : {"IN", "OUT"}) {
        const auto at = command.find(name + ".exr");
        command.replace(at, name.size() + 4, dir + (name == "IN" ? "/in.exr" : "/out.exr"));
    }
    const std::string line = "OCIO=" + sourceDir() + "/ocio/voxlux.ocio ocioconvert " + command + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(line.c_str()), 0) << line;
    Exr out = readExr(dir + "/out.exr");
    float worst = 0.0f;
    for (size_t i = 0; i < colours.size(); ++i) {
        glm::vec3 theirs(out.planes["R"][i], out.planes["G"][i], out.planes["B"][i]);
        glm::vec3 ours = expected(colours[i]);
        worst = std::max(worst, relativeError(theirs, ours));
    }
    std::printf("ocioconvert %s: worst relative difference %.2g\n", arguments.c_str(), double(worst));
    EXPECT_LE(worst, 1e-4f) << arguments;
}

TEST(Color, MatchesOcioconvert) {
    if (std::system("command -v ocioconvert > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "ocioconvert is not installed (Debian package opencolorio-tools): skipped";
    std::vector<glm::vec3> colours = hdrColours();
    ColorSettings out;
    out.output_space = "lin_rec709";
    ColorPipeline rec709 = pipelineOf(out);
    expectOcioconvertMatches("IN.exr ACEScg OUT.exr lin_rec709", colours, [&](glm::vec3 c) { return applyRgb(rec709.output, c); });
    out.output_space = "ACEScct";
    ColorPipeline cct = pipelineOf(out);
    expectOcioconvertMatches("IN.exr ACEScg OUT.exr ACEScct", colours, [&](glm::vec3 c) { return applyRgb(cct.output, c); });
    ColorPipeline view = pipelineOf({}, true);
    expectOcioconvertMatches("--view IN.exr ACEScg OUT.exr 'sRGB - Display' 'ACES 1.0 - SDR Video'", colours,
                             [&](glm::vec3 c) { return applyRgb(view.preview, c); });
    const std::string lut = sharedData("ocio/grading_test_files/lut3d_1.spi3d");
    if (lut.empty()) return;
    for (auto& c : colours) c = glm::min(c / 16.0f, glm::vec3(1.0f));  // a LUT's [0, 1] domain
    ColorSettings graded;
    graded.grade = {fileStep(GradeKind::Lut, lut)};
    ColorPipeline p = pipelineOf(graded);
    expectOcioconvertMatches("--lut " + lut + " IN.exr OUT.exr", colours, [&](glm::vec3 c) { return applyRgb(p.grade, c); });
}

}  // namespace
}  // namespace voxlux::test
