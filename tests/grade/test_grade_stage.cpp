// The grade stage end to end: what a render writes in its output space, what the grade touches
// (the beauty) and what it leaves alone (AOVs, alpha), CPU against GL, the preview PNG and the
// one-line errors of bad colour settings.
#include <filesystem>
#include <fstream>

#include <ImfChromaticitiesAttribute.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <png.h>

#include "render/grade_stage.h"
#include "render/renderer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {
namespace fs = std::filesystem;

// A small lit ball with the direct AOV, written as float so values compare exactly.
Scene ballScene(const std::string& dir) {
    Scene s;
    s.volume().path = writeBall(dir);
    s.volume().material.density_scale = 20.0f;
    Light key;
    key.direction = glm::normalize(glm::vec3(-1.0f, -1.0f, -0.5f));
    key.color = {1.0f, 0.8f, 0.6f};
    key.intensity = 4.0f;
    s.lights = {key};
    s.render.width = s.render.height = 48;
    s.render.backend = Backend::Cpu;
    s.output.pixel_type = PixelType::Float;
    s.output.aovs = {AovSpec{"direct", std::nullopt}};
    return s;
}

FrameResult renderScene(const Scene& s) {
    ::unsetenv("OCIO");
    Renderer renderer(s);
    return renderer.render(std::nullopt, false);
}

GradeStep warmCdl() {
    GradeStep g;
    g.kind = GradeKind::Cdl;
    g.slope = {1.2f, 1.0f, 0.8f};
    g.offset = {0.02f, 0.0f, 0.0f};
    g.space = "ACEScct";
    return g;
}

TEST(GradeStage, OutputSpaceConvertsBeautyAndAovsButNotAlpha) {
    const std::string dir = tempDir("grade-output");
    Scene s = ballScene(dir);
    FrameResult linear = renderScene(s);
    s.color.output_space = "ACES2065-1";
    FrameResult aces = renderScene(s);
    EXPECT_TRUE(std::any_of(aces.stage_seconds.begin(), aces.stage_seconds.end(), [](auto& st) { return st.first == "grade"; }));
    ColorSettings out;
    out.output_space = "ACES2065-1";
    ColorPipeline p = buildColorPipeline(out, false);
    auto cpu = p.output->getDefaultCPUProcessor();
    float worst = 0.0f, lit = 0.0f;
    for (size_t i = 0; i < linear.image.pixels.size(); ++i) {
        const auto &a = linear.image.pixels[i], &b = aces.image.pixels[i];
        float beauty[3] = {a.rgba.x, a.rgba.y, a.rgba.z}, direct[3] = {a.direct.x, a.direct.y, a.direct.z};
        cpu->applyRGB(beauty);
        cpu->applyRGB(direct);
        for (int c = 0; c < 3; ++c) {
            worst = std::max({worst, std::abs(beauty[c] - b.rgba[c]), std::abs(direct[c] - b.direct[c])});
            lit = std::max(lit, b.rgba[c]);
        }
        EXPECT_EQ(a.rgba.w, b.rgba.w);
        EXPECT_EQ(a.transmittance, b.transmittance);
    }
    std::printf("ACEScg -> ACES2065-1 render: max difference %.2g of peak %.3g\n", double(worst), double(lit));
    EXPECT_GT(lit, 0.05f);
    EXPECT_LE(worst, 1e-5f * lit);
}

TEST(GradeStage, GradeTouchesTheBeautyOnly) {
    const std::string dir = tempDir("grade-beauty");
    Scene s = ballScene(dir);
    FrameResult plain = renderScene(s);
    s.color.grade = {warmCdl()};
    FrameResult graded = renderScene(s);
    float changed = 0.0f;
    for (size_t i = 0; i < plain.image.pixels.size(); ++i) {
        const auto &a = plain.image.pixels[i], &b = graded.image.pixels[i];
        EXPECT_EQ(a.direct, b.direct) << "AOVs stay ungraded";
        EXPECT_EQ(a.rgba.w, b.rgba.w);
        if (a.rgba.w == 0.0f) {
            EXPECT_EQ(b.rgba, glm::vec4(0.0f)) << "the background is not lifted by the offset";
        }
        changed = std::max(changed, std::abs(b.rgba.x - a.rgba.x));
    }
    EXPECT_GT(changed, 0.01f);
}

// One image through a look, a CDL in ACEScct, an output space and a preview: both backends agree.
TEST(GradeStage, CpuAndGlAgree) {
    VOXLUX_REQUIRE_GL(gl);
    const std::string dir = tempDir("grade-backends");
    Scene s = ballScene(dir);
    FrameResult r = renderScene(s);
    ColorSettings color;
    GradeStep look;
    look.kind = GradeKind::Look;
    look.look = "ACES 1.3 Reference Gamut Compression";
    color.grade = {look, warmCdl()};
    color.output_space = "ACES2065-1";
    ::unsetenv("OCIO");
    ColorPipeline p = buildColorPipeline(color, true);
    RenderImage on_cpu = r.image, on_gl = r.image;
    std::vector<glm::vec4> preview_cpu = gradeImage(on_cpu, p, {"direct"}, *makeColorTransformer(Device::Cpu));
    std::vector<glm::vec4> preview_gl = gradeImage(on_gl, p, {"direct"}, *makeColorTransformer(gl->device()));
    float worst = 0.0f;
    for (size_t i = 0; i < on_cpu.pixels.size(); ++i)
        for (int c = 0; c < 4; ++c)
            worst = std::max({worst, std::abs(on_cpu.pixels[i].rgba[c] - on_gl.pixels[i].rgba[c]),
                              std::abs(preview_cpu[i][c] - preview_gl[i][c]),
                              c < 3 ? std::abs(on_cpu.pixels[i].direct[c] - on_gl.pixels[i].direct[c]) : 0.0f});
    std::printf("grade stage, cpu against gl: max difference %.2g\n", double(worst));
    EXPECT_LE(worst, 1e-4f);
}

// The EXR names its colour space and config and carries AP1 chromaticities; the preview is an
// 8-bit PNG whose lit pixels are brighter than its background.
TEST(GradeStage, CliWritesColourMetadataAndAPreview) {
    const std::string dir = tempDir("grade-cli");
    const std::string ball = writeBall(dir);
    CliResult r = runCli("render " + ball + " --res 40x30 --backend cpu -o " + dir + "/shot.exr --preview " + dir + "/shot.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Exr e = readExr(dir + "/shot.exr");
    auto* space = e.header.findTypedAttribute<Imf::StringAttribute>("oiio:ColorSpace");
    ASSERT_TRUE(space);
    EXPECT_EQ(space->value(), "ACEScg");
    auto* config = e.header.findTypedAttribute<Imf::StringAttribute>("voxlux/config");
    ASSERT_TRUE(config);
    EXPECT_EQ(config->value(), "voxlux built-in config (ocio/voxlux.ocio)");
    ASSERT_TRUE(Imf::hasChromaticities(e.header));
    EXPECT_NEAR(Imf::chromaticities(e.header).red.x, 0.713f, 1e-4f);
    EXPECT_NEAR(Imf::chromaticities(e.header).white.y, 0.33767f, 1e-4f);

    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&image, (dir + "/shot.png").c_str()));
    EXPECT_EQ(image.width, 40u);
    EXPECT_EQ(image.height, 30u);
    image.format = PNG_FORMAT_RGB;
    std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(image));
    ASSERT_TRUE(png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr));
    const int corner = pixels[0], centre = pixels[(15 * 40 + 20) * 3 + 1];
    EXPECT_EQ(corner, 0);
    EXPECT_GT(centre, 40);
}

void expectRejected(const std::string& scene_json, const std::string& message) {
    const std::string dir = tempDir("grade-rejected");
    writeBall(dir);
    std::ofstream(dir + "/shot.json") << scene_json;
    CliResult r = runCli("render " + dir + "/shot.json -o " + dir + "/out.exr --preview " + dir + "/out.png");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + message + "\n");
    EXPECT_FALSE(fs::exists(dir + "/out.exr"));
    EXPECT_FALSE(fs::exists(dir + "/out.png"));
}

TEST(GradeStage, BadColourSettingsAreRefusedBeforeRendering) {
    expectRejected(R"({"volume": {"path": "ball.vdb"}, "color": {"grade": [{"look": "Noir"}]}})",
                   "color.grade[0].look: no look 'Noir' in voxlux built-in config (ocio/voxlux.ocio) (it has: "
                   "ACES 1.3 Reference Gamut Compression, Warm)");
    const std::string dir = tempDir("grade-rejected");
    expectRejected(R"({"volume": {"path": "ball.vdb"}, "color": {"config": "missing.ocio"}})",
                   dir + "/missing.ocio: no such OCIO config (color.config)");
    std::ofstream(dir + "/broken.ocio") << "ocio_profile_version: 2\nroles: [\n";
    CliResult r = runCli("render " + dir + "/ball.vdb --set color.config='\"" + dir + "/broken.ocio\"' -o " + dir + "/out.exr");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err.rfind("voxlux: error: " + dir + "/broken.ocio: not a usable OCIO config (", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out.exr"));
}

}  // namespace
}  // namespace voxlux::test
