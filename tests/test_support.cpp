#include "test_support.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include "backend/backend_choice.h"
#include "core/error.h"
#include "graph/render_graph.h"
#include "io/exr_writer.h"
#include "scene/scene_json.h"
#include "volume/velocity.h"

namespace voxlux::test {
namespace fs = std::filesystem;

// The tests run the render graph with its stages' scene reads checked, as debug builds do: set
// as the test binary starts.
const bool kStageReadChecksOnInTests = (setStageReadChecks(true), true);

std::string sharedData(const std::string& relative) {
    const char* root = std::getenv("VOXLUX_SHARED_DATA");  // another checkout layout
    fs::path p = fs::path(root ? root : defaultSharedData()) / relative;
    return fs::exists(p) ? p.string() : std::string();
}

std::unique_ptr<KernelBackend> glBackendOrSkip() {
    const char* skip = std::getenv("VOXLUX_SKIP_GL");
    if (!VOXLUX_GL_BUILT || (skip && std::string(skip) == "1")) return nullptr;
    try {
        return makeGlBackend();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "no GL backend (set VOXLUX_SKIP_GL=1 to skip GL tests): " << e.what();
        return nullptr;
    }
}

LoadedVolume volumeFromGrid(openvdb::FloatGrid::Ptr density, std::vector<openvdb::FloatGrid::ConstPtr> emission,
                            openvdb::Vec3SGrid::Ptr color) {
    initOpenVdb();
    LoadedVolume v;
    v.file = "memory.vdb";
    v.index_to_world = indexToWorld(*density, v.file);
    v.density = density;
    v.emission = std::move(emission);
    v.color = color;
    return v;
}

openvdb::FloatGrid::Ptr boxGrid(openvdb::Coord lo, openvdb::Coord hi, float sigma, double voxel) {
    initOpenVdb();
    auto g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    g->denseFill(openvdb::CoordBBox(lo, hi), sigma, true);
    return g;
}

openvdb::FloatGrid::Ptr twoHalvesGrid(float left, float right) {
    auto grid = boxGrid({0, 0, 0}, {31, 31, 31}, right);
    grid->denseFill(openvdb::CoordBBox({0, 0, 0}, {15, 31, 31}), left, true);
    return grid;
}

double luminance(glm::vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

std::string writeMap(const std::string& path, int width, int height, const std::function<glm::vec3(int, int)>& radiance) {
    RenderImage image;
    image.width = width;
    image.height = height;
    image.pixels.resize(size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) image.pixels[size_t(y) * width + x].rgba = glm::vec4(radiance(x, y), 1.0f);
    OutputSpec spec;
    spec.pixel_type = PixelType::Float;
    writeExr(path, image, spec, ExrMetadata{});
    return path;
}

std::pair<double, double> meanLuminanceAndError(const RenderImage& img) {
    double sum = 0.0, variance = 0.0;
    for (const auto& p : img.pixels) {
        sum += luminance(glm::vec3(p.rgba));
        variance += p.variance;
    }
    const double n = double(img.pixels.size());
    return {sum / n, std::sqrt(variance) / n};
}

double cubicBSpline(double x) {
    x = std::abs(x);
    if (x < 1) return (4 - 6 * x * x + 3 * x * x * x) / 6;
    if (x < 2) return (2 - x) * (2 - x) * (2 - x) / 6;
    return 0;
}

Camera cameraAlong(glm::vec3 centre, glm::vec3 dir, float distance, float fov) {
    Camera c;
    c.look_at = centre;
    c.position = centre - glm::normalize(dir) * distance;
    c.up = std::abs(dir.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    c.fov = fov;
    return c;
}

std::unique_ptr<Prepared> prepare(LoadedVolume volume, const Scene& scene, const Camera& camera) {
    auto p = std::make_unique<Prepared>();
    p->volume = std::move(volume);
    p->atlas = buildBrickAtlas(p->volume, motionReachBricks(p->volume, scene.render.motion_blur));
    p->pages = classifiedPageTable(p->atlas, scene);
    p->inputs = makeKernelInputs(scene, p->atlas, p->pages, 0.0f, kXyzD65ToAcescg, {&camera, {}});
    return p;
}

CliResult runCli(const std::string& args) { return runShell(voxluxBinary() + " " + args); }

CliResult runShell(const std::string& command) {
    static int counter = 0;
    const std::string base = tempDir("cli") + "/run" + std::to_string(counter++);
    const std::string cmd = "(" + command + ") >" + base + ".out 2>" + base + ".err";
    int status = std::system(cmd.c_str());
    CliResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    auto slurp = [](const std::string& path) {
        std::ifstream in(path);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    };
    r.out = slurp(base + ".out");
    r.err = slurp(base + ".err");
    return r;
}

Exr readExr(const std::string& path) {
    Imf::InputFile file(path.c_str());
    Exr e;
    e.header = file.header();
    const auto dw = file.header().dataWindow();
    e.width = dw.max.x - dw.min.x + 1;
    e.height = dw.max.y - dw.min.y + 1;
    Imf::FrameBuffer fb;
    for (auto c = file.header().channels().begin(); c != file.header().channels().end(); ++c) {
        e.channels.push_back(c.name());
        auto& plane = e.planes[c.name()];
        plane.resize(size_t(e.width) * e.height);
        fb.insert(c.name(), Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(plane.data()), sizeof(float),
                                       sizeof(float) * e.width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return e;
}

std::string tempDir(const std::string& name) {
    fs::path p = fs::temp_directory_path() / ("voxlux-tests-" + std::to_string(::getpid())) / name;
    fs::create_directories(p);
    return p.string();
}

std::string linesStartingWith(const std::string& text, const std::string& prefix) {
    std::istringstream in(text);
    std::string out;
    for (std::string line; std::getline(in, line);)
        if (line.rfind(prefix, 0) == 0) out += line + "\n";
    return out;
}

ReadOnlyFolder::ReadOnlyFolder(const std::string& name) : path(tempDir(name)) {
    if (::geteuid() == 0) {
        mounted_ = std::system(("mount -t tmpfs -o ro,size=64k tmpfs '" + path + "' 2>/dev/null").c_str()) == 0;
        cause = "Read-only file system";
        if (!mounted_) problem = "cannot mount a read-only tmpfs on " + path + " (no mount rights)";
        return;
    }
    fs::permissions(path, fs::perms::owner_read | fs::perms::owner_exec);
    cause = "Permission denied";
}

ReadOnlyFolder::~ReadOnlyFolder() {
    if (mounted_) std::system(("umount '" + path + "'").c_str());
    else fs::permissions(path, fs::perms::owner_all);
}

std::unique_ptr<Lit> illuminate(openvdb::FloatGrid::Ptr grid, const Scene& scene, KernelBackend& backend,
                                const Camera& camera) {
    auto lit = std::make_unique<Lit>();
    lit->camera = camera;
    Scene seen = scene;
    seen.camera = camera;
    lit->renderer = std::make_unique<Renderer>(seen, volumeFromGrid(grid), backend);
    lit->result = lit->renderer->prepare(std::nullopt, false);
    return lit;
}

void Lit::relight(Scene scene) {
    scene.camera = camera;
    renderer->setScene(scene);
    result = renderer->prepare(std::nullopt, false);
}

std::string inputErrorOf(const std::function<void()>& action) {
    try {
        action();
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

float largestDifference(const glm::mat4& a, const glm::mat4& b) {
    float d = 0.0f;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) d = std::max(d, std::abs(a[c][r] - b[c][r]));
    return d;
}

std::string sceneErrorOf(const std::string& json) {
    return inputErrorOf([&] { parseScene(json, "shot.json", "/shots"); });
}

std::string writeBall(const std::string& dir) {
    auto grid = boxGrid({0, 0, 0}, {-1, -1, -1}, 0.0f, 0.1);  // empty, named density
    auto acc = grid->getAccessor();
    for (int z = -20; z <= 20; ++z)
        for (int y = -20; y <= 20; ++y)
            for (int x = -20; x <= 20; ++x) {
                const float r = std::sqrt(float(x * x + y * y + z * z)) / 20.0f;
                if (r <= 1.0f) acc.setValue({x, y, z}, (1.0f - r) * (1.2f + std::sin(0.5f * x) * std::cos(0.4f * y)));
            }
    const std::string path = dir + "/ball.vdb";
    openvdb::io::File(path).write({grid});
    return path;
}

void writeDepthExr(const std::string& path, int width, int height, const std::function<float(int, int)>& depth,
                   const std::string& channel) {
    std::vector<float> values(size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) values[size_t(y) * width + x] = depth(x, y);
    Imf::Header header(width, height);
    header.channels().insert(channel, Imf::Channel(Imf::FLOAT));
    Imf::FrameBuffer fb;
    fb.insert(channel, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), sizeof(float), sizeof(float) * size_t(width)));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(height);
}

RenderImage renderScene(const Scene& scene) { return Renderer(scene).render(std::nullopt, false).image; }

std::string writeFireBall(const std::string& dir) {
    auto density = boxGrid({0, 0, 0}, {-1, -1, -1}, 0.0f, 0.1);
    auto heat = boxGrid({0, 0, 0}, {-1, -1, -1}, 0.0f, 0.1);
    heat->setName("heat");
    auto colour = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    colour->setTransform(density->transform().copy());
    colour->setName("Cd");
    auto d = density->getAccessor();
    auto h = heat->getAccessor();
    auto c = colour->getAccessor();
    for (int z = -24; z <= 24; ++z)
        for (int y = -24; y <= 24; ++y)
            for (int x = -24; x <= 24; ++x) {
                const float r = std::sqrt(float(x * x + y * y + z * z)) / 20.0f, u = float(x + 24) / 48.0f;
                if (r <= 1.0f) d.setValue({x, y, z}, 1.0f - r);
                if (r <= 1.0f) c.setValue({x, y, z}, openvdb::Vec3s(1.0f - 0.6f * u, 0.6f, 0.3f + 0.7f * u));
                if (r <= 1.2f) h.setValue({x, y, z}, 1.0f - r / 1.2f);
            }
    const std::string path = dir + "/fire.vdb";
    auto velocity = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    velocity->setTransform(density->transform().copy());
    velocity->setName("vel");
    velocity->denseFill(openvdb::CoordBBox({-28, -28, -28}, {28, 28, 28}), openvdb::Vec3s(2.0f, 0.0f, 0.0f), true);
    openvdb::io::File(path).write({density, heat, colour, velocity});
    return path;
}

}  // namespace voxlux::test
