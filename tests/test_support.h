// Helpers shared by the tests: synthetic volumes, the shared real-data folder, running the CLI.
#pragma once
#include <functional>
#include <optional>
#include <string>

#include <map>
#include <vector>

#include <ImfHeader.h>
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include "volume/brick_atlas.h"
#include "kernel/kernel_inputs.h"
#include "lighting/propagation/kernel/illumination_volume.h"
#include "render/renderer.h"
#include "kernel/kernel_backend.h"
#include "volume/page_table.h"
#include "scene/scene.h"
#include "volume/vdb_loader.h"

namespace voxlux::test {

// Where this build's files are (test_paths.cpp, which CMake generates): read at run time, so that
// no test's compile line holds an absolute path and a clone in another folder, as CI's, hits
// ccache. Plain values, safe to read while other files' statics are made.
std::string sourceDir();          // the repository
std::string voxluxBinary();       // the voxlux program under test
std::string defaultSharedData();  // ../shared/data beside the repository
std::string layerLibraries();     // every layer's static library, comma-separated (Layers.*)

// Path of a file in ../shared/data (or $VOXLUX_SHARED_DATA), or empty when it is absent: a
// user's fresh clone has no ../shared, CI does; VOXLUX_REQUIRE_SHARED then skips with a message.
std::string sharedData(const std::string& relative);
#define VOXLUX_REQUIRE_SHARED(var, relative)                                                   \
    const std::string var = ::voxlux::test::sharedData(relative);                               \
    if (var.empty()) GTEST_SKIP() << "../shared/data/" relative " is absent (fresh clone): skipped"

// The one-line InputError `action` throws, or "no error".
std::string inputErrorOf(const std::function<void()>& action);

// The one-line InputError parsing `json` as "shot.json" in "/shots" gives, or "no error".
std::string sceneErrorOf(const std::string& json);

// GL backend for tests: fails the test when no context can be made, unless VOXLUX_SKIP_GL=1 or
// the build has no GL backend (VOXLUX_GL=OFF); then null.
std::unique_ptr<KernelBackend> glBackendOrSkip();
#define VOXLUX_REQUIRE_GL(var)                                                                  \
    auto var = ::voxlux::test::glBackendOrSkip();                                               \
    if (!var) GTEST_SKIP() << "no GL backend (VOXLUX_GL=OFF build, or VOXLUX_SKIP_GL=1): skipped"

// A fog grid in memory, as the loader would return it.
// `emission`: one grid per emission source of the scene it renders with.
LoadedVolume volumeFromGrid(openvdb::FloatGrid::Ptr density,
                            std::vector<openvdb::FloatGrid::ConstPtr> emission = {},
                            openvdb::Vec3SGrid::Ptr color = nullptr);

// A constant-density box of `sigma` over index voxels [lo, hi] (inclusive), voxel size `voxel`.
openvdb::FloatGrid::Ptr boxGrid(openvdb::Coord lo, openvdb::Coord hi, float sigma, double voxel = 1.0);

// A 32^3 cube of voxels 0..31 whose half x < 16 holds `left` and the rest `right`: two materials a
// 2D transfer function tells apart by value alone.
openvdb::FloatGrid::Ptr twoHalvesGrid(float left, float right);

// A noisy ball of radius 20 voxels (voxel 0.1) written to `dir`/ball.vdb; returns the path. A
// file, since the renderer keys its caches on it.
std::string writeBall(const std::string& dir);

// A ball of radius 20 voxels (voxel 0.1) written to `dir`/fire.vdb with a "heat" grid beside its
// density, 1 at the centre and 0 at 1.2 times the density's radius (it emits where the density
// has faded out, too), a colour grid "Cd" that turns from orange to blue along x, and a velocity
// "vel" of 2 world units a second along x; returns the path.
std::string writeFireBall(const std::string& dir);

// A float EXR at `path` of one channel `channel` whose pixel (x, y) holds depth(x, y): a CG
// render's depth, for a holdout.
void writeDepthExr(const std::string& path, int width, int height, const std::function<float(int, int)>& depth,
                   const std::string& channel = "Z");

// The image of `scene` (its files read from disk), rendered once by a Renderer of its own.
RenderImage renderScene(const Scene& scene);

// The largest difference of any element of two matrices.
float largestDifference(const glm::mat4& a, const glm::mat4& b);

// Rec. 709 luminance of scene-linear RGB.
double luminance(glm::vec3 rgb);

// A float EXR of `width` x `height` pixels whose pixel (x, y) holds radiance(x, y): an environment
// map. Returns `path`.
std::string writeMap(const std::string& path, int width, int height, const std::function<glm::vec3(int, int)>& radiance);

// An image's mean luminance and its standard error (from the reference's per-pixel variances).
std::pair<double, double> meanLuminanceAndError(const RenderImage& img);

// The uniform cubic B-spline centred on a grid point, at distance x from it: the brute-force
// weights the tricubic filters are tested against.
double cubicBSpline(double x);

// A camera `distance` from `centre`, looking at it along `dir`, with field of view `fov` (degrees).
Camera cameraAlong(glm::vec3 centre, glm::vec3 dir, float distance, float fov);

// Everything one render needs, kept alive together.
struct Prepared {
    LoadedVolume volume;
    BrickAtlas atlas;
    PageTable pages;
    KernelInputs inputs;
};
std::unique_ptr<Prepared> prepare(LoadedVolume volume, const Scene& scene, const Camera& camera);

// A scene lit through the render graph (every stage but the march) over a grid in memory.
struct Lit {
    std::unique_ptr<Renderer> renderer;
    Camera camera;
    FrameResult result;                    // of the last update
    const IlluminationVolume& volume() const { return *renderer->lightingOutput<IlluminationVolume>(); }
    const LightUpdate& update() const { return *result.light_update; }
    // Lights `scene` (seen from the same camera) on the same renderer: only what changed re-runs.
    void relight(Scene scene);
};
// Lights `scene` over `grid` on `backend`, seen from `camera`.
std::unique_ptr<Lit> illuminate(openvdb::FloatGrid::Ptr grid, const Scene& scene, KernelBackend& backend,
                                const Camera& camera);

struct CliResult {
    int exit_code = -1;
    std::string out;
    std::string err;
};
// Runs the voxlux binary with `args` (shell-quoted by the caller where needed).
CliResult runCli(const std::string& args);
// Runs a shell command line, its output captured.
CliResult runShell(const std::string& command);

// An EXR read back through the OpenEXR API: every channel as float, and the header.
struct Exr {
    int width = 0, height = 0;
    std::vector<std::string> channels;
    std::map<std::string, std::vector<float>> planes;
    Imf::Header header;
};
Exr readExr(const std::string& path);

// The lines of `text` that start with `prefix` ("voxlux: error: "), each with its newline: what a
// test checks of standard error among the notes and progress lines beside it.
std::string linesStartingWith(const std::string& text, const std::string& prefix);

// A folder under this test run's temp dir (created if needed).
std::string tempDir(const std::string& name);

// A folder nothing can be written in, as a read-only file system is: as root (whom permissions do
// not stop) a read-only tmpfs mounted on it, else its write bits cleared. Undone when it goes.
// `problem` is set when neither works (a root without mount rights), and a test then skips.
class ReadOnlyFolder {
public:
    explicit ReadOnlyFolder(const std::string& name);
    ~ReadOnlyFolder();
    ReadOnlyFolder(const ReadOnlyFolder&) = delete;
    ReadOnlyFolder& operator=(const ReadOnlyFolder&) = delete;
    const std::string path;
    std::string problem;   // "" when the folder refuses writes
    std::string cause;     // what writing in it says: "Read-only file system" or "Permission denied"

private:
    bool mounted_ = false;
};

}  // namespace voxlux::test
