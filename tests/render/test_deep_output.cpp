// Deep output (output.deep; shaders/vx_deep.h, src/io/deep_exr_writer.cpp): OpenEXR's own
// CompositeDeepScanLine flattens the deep image to the flat beauty; samples are ordered, at most
// output.deep_samples a pixel, and split at empty gaps, so a holdout plane between two boxes
// leaves exactly the front box; the GL backend's samples flatten the same.
#include <ImfChannelList.h>
#include <ImfCompositeDeepScanLine.h>
#include <ImfDeepScanLineInputFile.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfPartType.h>
#include <ImfStringAttribute.h>

#include <filesystem>

#include "backend/backend_choice.h"
#include "io/deep_exr_writer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// Two boxes along the camera's view, 8 voxels deep each, with 12 empty voxels between them; the
// camera looks down -z from 50 voxels away from the middle.
openvdb::FloatGrid::Ptr twoBoxes(bool back_box) {
    auto grid = boxGrid({0, 0, 20}, {15, 15, 27}, 0.15f);
    if (back_box) grid->denseFill(openvdb::CoordBBox({2, 2, 0}, {13, 13, 7}), 0.3f, true);
    return grid;
}

Scene deepScene(ShadowMethod shadows, int deep_samples) {
    Scene scene;
    scene.render.width = 24;
    scene.render.height = 24;
    scene.output.pixel_type = PixelType::Float;
    scene.output.deep = true;
    scene.output.deep_samples = deep_samples;
    scene.effects.shadows = shadows;
    Light key;
    key.type = LightType::Directional;
    key.direction = glm::normalize(glm::vec3(1.0f, -1.0f, -0.3f));
    key.intensity = 3.0f;
    Light sky;
    sky.type = LightType::Ambient;
    sky.intensity = 0.4f;
    scene.lights = {key, sky};
    scene.camera = cameraAlong({8.0f, 8.0f, 14.0f}, {0.0f, 0.0f, -1.0f}, 50.0f, 30.0f);
    return scene;
}

// Renders `scene` over `grid` to `dir`/out.exr and out.deep.exr on `backend`.
FrameResult renderFiles(Scene scene, openvdb::FloatGrid::Ptr grid, KernelBackend& backend, const std::string& dir) {
    scene.output.path = dir + "/out.exr";
    Renderer renderer(scene, volumeFromGrid(grid), backend);
    return renderer.renderToFile(std::nullopt, false);
}

struct Flat {
    int width = 0, height = 0;
    std::vector<float> r, g, b, a;
};

// The deep files composited by OpenEXR (sorted by Z, "over"), as Nuke's DeepToImage does.
Flat composite(const std::vector<std::string>& deep_files) {
    std::vector<std::unique_ptr<Imf::DeepScanLineInputFile>> files;
    Imf::CompositeDeepScanLine comp;
    for (const auto& f : deep_files) {
        files.push_back(std::make_unique<Imf::DeepScanLineInputFile>(f.c_str()));
        comp.addSource(files.back().get());
    }
    const Imath::Box2i window = files[0]->header().dataWindow();
    Flat out;
    out.width = window.max.x - window.min.x + 1;
    out.height = window.max.y - window.min.y + 1;
    Imf::FrameBuffer fb;
    const size_t n = size_t(out.width) * out.height;
    std::pair<const char*, std::vector<float>*> channels[] = {{"R", &out.r}, {"G", &out.g}, {"B", &out.b}, {"A", &out.a}};
    for (auto& [name, plane] : channels) {
        plane->resize(n);
        fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(plane->data()), sizeof(float), sizeof(float) * out.width));
    }
    comp.setFrameBuffer(fb);
    comp.readPixels(window.min.y, window.max.y);
    return out;
}

void expectFlattensToTheBeauty(const std::string& dir, const char* what) {
    const Flat flat = composite({dir + "/out.deep.exr"});
    Exr beauty = readExr(dir + "/out.exr");
    ASSERT_EQ(flat.r.size(), beauty.planes["R"].size());
    double peak = 0.0, worst = 0.0;
    const std::pair<const std::vector<float>*, std::string> planes[] = {{&flat.r, "R"}, {&flat.g, "G"}, {&flat.b, "B"}, {&flat.a, "A"}};
    for (const auto& [deep, name] : planes)
        for (size_t i = 0; i < deep->size(); ++i) {
            if (name != "A") peak = std::max(peak, double(beauty.planes[name][i]));
            worst = std::max(worst, std::abs(double((*deep)[i]) - beauty.planes[name][i]) / std::max(1.0, double(beauty.planes[name][i])));
        }
    EXPECT_GT(peak, 0.05) << what;          // something was rendered
    EXPECT_LE(worst, 1e-4) << what;
}

// Every pixel's samples in order: z < z_back <= the next sample's z; at most `limit` of them.
void expectOrderedSamples(const RenderImage& image, int limit, uint32_t& most) {
    size_t at = 0;
    most = 0;
    for (uint32_t count : image.deep.counts) {
        ASSERT_LE(count, uint32_t(limit));
        most = std::max(most, count);
        for (uint32_t i = 0; i < count; ++i) {
            const kernel::VxDeepSample& s = image.deep.samples[at + i];
            EXPECT_LT(s.z, s.z_back);
            EXPECT_GE(s.alpha, 0.0f);
            EXPECT_LE(s.alpha, 1.0f);
            if (i + 1 < count) {
                EXPECT_LE(s.z_back, image.deep.samples[at + i + 1].z);
            }
        }
        at += count;
    }
    EXPECT_EQ(at, image.deep.samples.size());
}

TEST(DeepOutput, OpenExrFlattensTheDeepImageToTheBeauty) {
    const std::string dir = tempDir("deep_flatten");
    auto cpu = makeCpuBackend();
    // Ray-marched shadows: the march's per-sample path; unshadowed directional light: its
    // per-chunk path. Two samples a pixel: the merges.
    for (auto [shadows, limit] : {std::pair{ShadowMethod::Raymarch, 16}, std::pair{ShadowMethod::None, 16}, std::pair{ShadowMethod::Raymarch, 2}}) {
        const FrameResult r = renderFiles(deepScene(shadows, limit), twoBoxes(true), *cpu, dir);
        uint32_t most = 0;
        expectOrderedSamples(r.image, limit, most);
        // The gap splits: at least a sample a box; with a limit of 2, merges keep 2.
        EXPECT_GE(most, 2u);
        if (limit == 2) {
            EXPECT_EQ(most, 2u);
        }
        expectFlattensToTheBeauty(dir, limit == 2 ? "merged to 2" : shadows == ShadowMethod::None ? "unshadowed" : "raymarch");
    }
}

// A black, opaque plane in the gap between the boxes, merged with OpenEXR: what remains is the
// front box alone, as a flat render of it gives; in front of both boxes the plane hides them.
TEST(DeepOutput, AHoldoutPlaneBetweenTheBoxesLeavesTheFrontBox) {
    const std::string dir = tempDir("deep_holdout");
    auto cpu = makeCpuBackend();
    const Scene scene = deepScene(ShadowMethod::None, 16);
    const FrameResult both = renderFiles(scene, twoBoxes(true), *cpu, dir);
    const auto plane = [&](float z) {
        RenderImage holdout;
        holdout.width = both.image.width;
        holdout.height = both.image.height;
        holdout.pixels.resize(both.image.pixels.size());
        holdout.deep.counts.assign(holdout.pixels.size(), 1);
        kernel::VxDeepSample s;
        s.rgb = glm::vec3(0.0f);
        s.alpha = 1.0f;
        s.z = z;
        s.z_back = z;
        holdout.deep.samples.assign(holdout.pixels.size(), s);
        writeDeepExr(dir + "/plane.deep.exr", holdout, scene.output, ExrMetadata{});
    };
    // The camera is 50 voxels from z = 14: the front box spans depths 36-44, the back one 56-64.
    plane(50.0f);
    const Flat held = composite({dir + "/out.deep.exr", dir + "/plane.deep.exr"});
    std::filesystem::create_directories(dir + "/front");
    renderFiles(scene, twoBoxes(false), *cpu, dir + "/front");
    Exr front = readExr(dir + "/front/out.exr");
    double worst = 0.0, covered = 0.0;
    for (size_t i = 0; i < held.r.size(); ++i) {
        worst = std::max({worst, std::abs(double(held.r[i]) - front.planes["R"][i]), std::abs(double(held.b[i]) - front.planes["B"][i])});
        covered += front.planes["A"][i] > 0.0f;
    }
    EXPECT_GT(covered, 50);
    EXPECT_LE(worst, 1e-5);
    plane(30.0f);
    const Flat hidden = composite({dir + "/out.deep.exr", dir + "/plane.deep.exr"});
    for (size_t i = 0; i < hidden.r.size(); ++i) {
        ASSERT_EQ(hidden.r[i], 0.0f);
        ASSERT_EQ(hidden.a[i], 1.0f);
    }
}

// --deep writes NAME.deep.exr beside the image, with the channels Nuke's DeepRead expects and the
// image's metadata; --resume renders a frame again when its deep image is missing.
TEST(DeepOutput, TheDeepFlagWritesNukesChannelsBesideTheImage) {
    const std::string dir = tempDir("deep_cli");
    const std::string args = "render " + sourceDir() + "/grids/cloud.vdb --res 16x16 --backend cpu --deep -o " + dir + "/c.exr";
    CliResult r = runCli(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Imf::DeepScanLineInputFile deep((dir + "/c.deep.exr").c_str());
    EXPECT_EQ(deep.header().type(), Imf::DEEPSCANLINE);
    std::vector<std::string> channels;
    for (auto c = deep.header().channels().begin(); c != deep.header().channels().end(); ++c) channels.push_back(c.name());
    EXPECT_EQ(channels, (std::vector<std::string>{"A", "B", "G", "R", "Z", "ZBack"}));
    EXPECT_EQ(deep.header().channels().findChannel("Z")->type, Imf::FLOAT);
    EXPECT_EQ(deep.header().typedAttribute<Imf::StringAttribute>("voxlux/sceneHash").value(),
              readExr(dir + "/c.exr").header.typedAttribute<Imf::StringAttribute>("voxlux/sceneHash").value());
    std::filesystem::remove(dir + "/c.deep.exr");
    r = runCli(args + " --resume");
    EXPECT_EQ(r.out.rfind("wrote " + dir + "/c.exr", 0), 0u) << r.out;
    EXPECT_TRUE(std::filesystem::exists(dir + "/c.deep.exr"));
    r = runCli(args + " --method reference");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: --method: /output: deep is a march-only output (render.method is \"reference\"): the Monte Carlo "
                     "reference writes no deep samples\n");
}

TEST(DeepOutput, GlSamplesFlattenAsTheCpusOnGl) {
    VOXLUX_REQUIRE_GL(gl);
    const std::string dir = tempDir("deep_gl");
    const FrameResult r = renderFiles(deepScene(ShadowMethod::Raymarch, 4), twoBoxes(true), *gl, dir);
    uint32_t most = 0;
    expectOrderedSamples(r.image, 4, most);
    EXPECT_GE(most, 2u);
    expectFlattensToTheBeauty(dir, "gl");
    // The same samples as the CPU's, to float rounding.
    auto cpu = makeCpuBackend();
    const FrameResult c = renderFiles(deepScene(ShadowMethod::Raymarch, 4), twoBoxes(true), *cpu, dir);
    ASSERT_EQ(c.image.deep.counts, r.image.deep.counts);
    for (size_t i = 0; i < c.image.deep.samples.size(); ++i) {
        EXPECT_NEAR(c.image.deep.samples[i].alpha, r.image.deep.samples[i].alpha, 1e-5);
        EXPECT_NEAR(c.image.deep.samples[i].z, r.image.deep.samples[i].z, 1e-4);
        EXPECT_NEAR(c.image.deep.samples[i].rgb.x, r.image.deep.samples[i].rgb.x, 1e-4 * std::max(1.0f, c.image.deep.samples[i].rgb.x));
    }
}

}  // namespace
}  // namespace voxlux::test
