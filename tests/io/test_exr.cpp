// The EXR and PNG writers, read back through the OpenEXR API, OpenEXR's own command-line tools and
// libpng: exactly the layers asked for, in their pixel types, with every metadata attribute and
// value; a PNG that cannot be written leaves nothing behind.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <half.h>
#include <ImfChannelList.h>
#include <ImfFloatAttribute.h>
#include <ImfIntAttribute.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <glm/gtc/matrix_transform.hpp>
#include <png.h>

#include "core/error.h"
#include "io/exr_reader.h"
#include "io/exr_writer.h"
#include "io/png_writer.h"
#include "test_support.h"

namespace voxlux::test {
namespace {
namespace fs = std::filesystem;

constexpr int kWidth = 37, kHeight = 23;  // odd sizes: partial DWA blocks and tiles at the edges

// Every channel of the image, in VxPixel's order; a channel's index picks its pattern.
const std::vector<std::string> kChannels{
    "R",          "G",          "B",          "A",          "direct.R",   "direct.G",
    "direct.B",   "ambient.R",  "ambient.G",  "ambient.B",  "emission.R", "emission.G",
    "emission.B", "indirect.R", "indirect.G", "indirect.B", "transmittance.Y", "depth.Z"};

// A smooth value in [0.05, 0.75] that differs between channels; depth gets distances whose float
// digits half would lose. Computed once: the same expression compiled at two sites may round
// differently (FMA contraction), and the values read back must equal those written to the bit.
const std::vector<std::vector<float>>& patternPlanes() {
    static const std::vector<std::vector<float>> planes = [] {
        std::vector<std::vector<float>> p(kChannels.size(), std::vector<float>(size_t(kWidth) * kHeight));
        for (size_t c = 0; c < p.size(); ++c)
            for (int y = 0; y < kHeight; ++y)
                for (int x = 0; x < kWidth; ++x) {
                    const float v = 0.4f + 0.2f * std::sin(0.3f * x + 0.7f * c) + 0.15f * std::cos(0.2f * y - 0.4f * c);
                    p[c][size_t(y) * kWidth + x] = kChannels[c] == "depth.Z" ? 10.0f + 5.0f * v : v;
                }
        return p;
    }();
    return planes;
}

const std::vector<float>& expected(const std::string& channel) {
    return patternPlanes()[std::find(kChannels.begin(), kChannels.end(), channel) - kChannels.begin()];
}

RenderImage patternImage() {
    const auto& planes = patternPlanes();
    RenderImage img;
    img.width = kWidth;
    img.height = kHeight;
    img.pixels.resize(size_t(kWidth) * kHeight);
    for (size_t i = 0; i < img.pixels.size(); ++i) {
        kernel::VxPixel& p = img.pixels[i];
        for (int k = 0; k < 4; ++k) p.rgba[k] = planes[k][i];
        for (int k = 0; k < 3; ++k) {
            p.direct[k] = planes[4 + k][i];
            p.ambient[k] = planes[7 + k][i];
            p.emission[k] = planes[10 + k][i];
            p.indirect[k] = planes[13 + k][i];
        }
        p.transmittance = planes[16][i];
        p.depth = planes[17][i];
    }
    return img;
}

// Metadata with every field set to a value that is easy to recognise.
ExrMetadata fullMetadata() {
    ExrMetadata meta;
    meta.world_to_camera = glm::lookAt(glm::vec3(1, 2, 9), glm::vec3(0.5f, 0, 0), glm::vec3(0, 1, 0));
    meta.world_to_ndc = glm::perspective(0.7f, float(kWidth) / kHeight, 0.1f, 100.0f) * meta.world_to_camera;
    meta.scene_hash = "0123456789abcdef";
    meta.frame = 42;
    meta.stage_seconds = {{"load", 0.25}, {"march", 1.5}};
    meta.color_space = "ACEScg";
    meta.color_config = "studio-config-v1.0.0_aces-v1.3_ocio-v2.1";
    meta.chromaticities = std::array<glm::vec2, 4>{glm::vec2(0.713f, 0.293f), glm::vec2(0.165f, 0.830f),
                                                   glm::vec2(0.128f, 0.044f), glm::vec2(0.32168f, 0.33767f)};
    return meta;
}

OutputSpec spec(PixelType type, const std::string& compression, std::vector<AovSpec> aovs) {
    OutputSpec s;
    s.pixel_type = type;
    s.compression = compression;
    s.aovs = std::move(aovs);
    return s;
}

Imf::PixelType typeOf(const Exr& e, const std::string& channel) {
    return e.header.channels().findChannel(channel)->type;
}

// Every pixel of `channel` is the pattern as stored: rounded to half for HALF channels.
void expectPattern(const Exr& e, const std::string& channel) {
    const bool half = typeOf(e, channel) == Imf::HALF;
    const auto& plane = e.planes.at(channel);
    const auto& want = expected(channel);
    for (size_t i = 0; i < plane.size(); ++i)
        ASSERT_EQ(plane[i], half ? float(Imath::half(want[i])) : want[i]) << channel << " at pixel " << i;
}

void expectMatrix(const Imath::M44f& got, const glm::mat4& want, const char* name) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_EQ(got[i][j], want[i][j]) << name << "[" << i << "][" << j << "]";
}

std::string stringAttribute(const Exr& e, const char* name) {
    return e.header.typedAttribute<Imf::StringAttribute>(name).value();
}

std::set<std::string> attributeNames(const Imf::Header& header) {
    std::set<std::string> names;
    for (auto a = header.begin(); a != header.end(); ++a) names.insert(a.name());
    return names;
}

struct ToolRun {
    int exit_code = -1;
    std::string out;  // stdout and stderr
};
// Runs one of OpenEXR's tools; nullopt when it is not installed.
std::optional<ToolRun> runTool(const std::string& tool, const std::string& args) {
    if (std::system(("command -v " + tool + " >/dev/null 2>&1").c_str()) != 0) return std::nullopt;
    FILE* pipe = ::popen((tool + " " + args + " 2>&1").c_str(), "r");
    if (!pipe) return std::nullopt;
    ToolRun r;
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) r.out.append(buf, n);
    const int status = ::pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}
#define VOXLUX_REQUIRE_TOOL(var, tool, args)                                                        \
    const std::optional<ToolRun> var = runTool(tool, args);                                         \
    if (!var) GTEST_SKIP() << tool " is not installed (Debian package openexr): skipped";           \
    ASSERT_EQ(var->exit_code, 0) << var->out

// The AOVs of the layers test: direct in the output's half, emission asking for float, depth
// float by default.
const std::vector<AovSpec> kAovs{{"direct", std::nullopt}, {"emission", PixelType::Float},
                                 {"transmittance", std::nullopt}, {"depth", std::nullopt}};
const std::vector<std::string> kWritten{"A",          "B",          "G",          "R",
                                        "depth.Z",    "direct.B",   "direct.G",   "direct.R",
                                        "emission.B", "emission.G", "emission.R", "transmittance.Y"};

std::string writeLayersFile() {
    const std::string path = tempDir("exr_layers") + "/layers.exr";
    const ExrWriteReport report = writeExr(path, patternImage(), spec(PixelType::Half, "zip", kAovs), fullMetadata());
    EXPECT_EQ(report.non_finite, 0u);
    EXPECT_EQ(report.half_overflow, 0u);
    return path;
}

TEST(Exr, ExactlyTheRequestedLayersInTheirPixelTypes) {
    const Exr e = readExr(writeLayersFile());
    EXPECT_EQ(e.channels, kWritten);  // OpenEXR lists channels sorted by name
    for (const auto& c : kWritten) {
        const bool isFloat = c.starts_with("emission.") || c == "depth.Z";
        EXPECT_EQ(typeOf(e, c), isFloat ? Imf::FLOAT : Imf::HALF) << c;
        expectPattern(e, c);
    }

    // The other way round: float output, ambient following it, depth asking for half.
    const std::string path = tempDir("exr_layers") + "/float.exr";
    writeExr(path, patternImage(),
             spec(PixelType::Float, "zip", {{"ambient", std::nullopt}, {"depth", PixelType::Half}}), ExrMetadata{});
    const Exr f = readExr(path);
    EXPECT_EQ(f.channels, (std::vector<std::string>{"A", "B", "G", "R", "ambient.B", "ambient.G", "ambient.R", "depth.Z"}));
    for (const auto& c : f.channels) {
        EXPECT_EQ(typeOf(f, c), c == "depth.Z" ? Imf::HALF : Imf::FLOAT) << c;
        expectPattern(f, c);
    }
}

TEST(Exr, EveryMetadataAttributeWithItsValue) {
    const Exr e = readExr(writeLayersFile());
    const ExrMetadata meta = fullMetadata();
    const Imath::Box2i window({0, 0}, {kWidth - 1, kHeight - 1});
    EXPECT_EQ(e.header.dataWindow(), window);
    EXPECT_EQ(e.header.displayWindow(), window);
    EXPECT_EQ(e.header.compression(), Imf::ZIP_COMPRESSION);
    expectMatrix(Imf::worldToCameraAttribute(e.header).value(), meta.world_to_camera, "worldToCamera");
    expectMatrix(Imf::worldToNDCAttribute(e.header).value(), meta.world_to_ndc, "worldToNDC");
    const Imf::Chromaticities c = Imf::chromaticitiesAttribute(e.header).value();
    EXPECT_EQ(c.red, Imath::V2f(0.713f, 0.293f));
    EXPECT_EQ(c.green, Imath::V2f(0.165f, 0.830f));
    EXPECT_EQ(c.blue, Imath::V2f(0.128f, 0.044f));
    EXPECT_EQ(c.white, Imath::V2f(0.32168f, 0.33767f));
    EXPECT_EQ(stringAttribute(e, "oiio:ColorSpace"), "ACEScg");
    EXPECT_EQ(stringAttribute(e, "voxlux/colorSpace"), "ACEScg");
    EXPECT_EQ(stringAttribute(e, "voxlux/config"), "studio-config-v1.0.0_aces-v1.3_ocio-v2.1");
    EXPECT_EQ(stringAttribute(e, "voxlux/version"), VOXLUX_VERSION);
    EXPECT_EQ(stringAttribute(e, "voxlux/sceneHash"), "0123456789abcdef");
    EXPECT_EQ(e.header.typedAttribute<Imf::IntAttribute>("voxlux/frame").value(), 42);
    EXPECT_EQ(e.header.typedAttribute<Imf::FloatAttribute>("voxlux/exposure").value(), 0.0f);
    EXPECT_EQ(e.header.typedAttribute<Imf::FloatAttribute>("voxlux/seconds/load").value(), 0.25f);
    EXPECT_EQ(e.header.typedAttribute<Imf::FloatAttribute>("voxlux/seconds/march").value(), 1.5f);

    // Nothing else: OpenEXR's required attributes and voxlux's.
    const std::set<std::string> required{"channels",         "compression",       "dataWindow",
                                         "displayWindow",    "lineOrder",         "pixelAspectRatio",
                                         "screenWindowCenter", "screenWindowWidth"};
    std::set<std::string> all = required;
    all.insert({"worldToCamera", "worldToNDC", "chromaticities", "oiio:ColorSpace", "voxlux/colorSpace",
                "voxlux/config", "voxlux/version", "voxlux/sceneHash", "voxlux/frame", "voxlux/exposure", "voxlux/seconds/load",
                "voxlux/seconds/march"});
    EXPECT_EQ(attributeNames(e.header), all);

    // Unset fields write nothing: no empty colour space, no frame outside a sequence (exposure 0 is
    // written: it says the image was not exposed).
    const std::string bare = tempDir("exr_layers") + "/bare.exr";
    writeExr(bare, patternImage(), spec(PixelType::Half, "zip", {}), ExrMetadata{});
    std::set<std::string> minimal = required;
    minimal.insert({"worldToCamera", "worldToNDC", "voxlux/version", "voxlux/sceneHash", "voxlux/exposure"});
    EXPECT_EQ(attributeNames(readExr(bare).header), minimal);
}

// exrheader, OpenEXR's own header dump, sees every layer in its type and every attribute.
TEST(Exr, ExrheaderListsEveryLayerAndAttribute) {
    const std::string path = writeLayersFile();
    VOXLUX_REQUIRE_TOOL(dump, "exrheader", path);
    const Exr e = readExr(path);
    for (const auto& c : kWritten) {
        const char* type = typeOf(e, c) == Imf::HALF ? "16-bit floating-point" : "32-bit floating-point";
        EXPECT_NE(dump->out.find("    " + c + ", " + type + ", sampling 1 1\n"), std::string::npos) << c << dump->out;
    }
    for (const auto& name : attributeNames(e.header))
        EXPECT_NE(dump->out.find("\n" + name + " (type "), std::string::npos) << name << dump->out;
    for (const char* line : {"oiio:ColorSpace (type string): \"ACEScg\"\n", "voxlux/frame (type int): 42\n",
                             "voxlux/seconds/march (type float): 1.5\n",
                             "voxlux/sceneHash (type string): \"0123456789abcdef\"\n",
                             "compression (type compression): zip, multi-scanline blocks\n"})
        EXPECT_NE(dump->out.find(line), std::string::npos) << line << dump->out;
}

// exrmaketiled reads every channel and writes them again, tiled: all survive with equal values.
TEST(Exr, ExrmaketiledReadsEveryLayer) {
    const std::string path = writeLayersFile();
    const std::string tiled = tempDir("exr_layers") + "/tiled.exr";
    VOXLUX_REQUIRE_TOOL(run, "exrmaketiled", "-t 16 16 " + path + " " + tiled);
    const Exr original = readExr(path), copy = readExr(tiled);
    ASSERT_TRUE(copy.header.hasTileDescription());
    EXPECT_EQ(copy.channels, kWritten);
    for (const auto& c : kWritten) {
        EXPECT_EQ(typeOf(copy, c), typeOf(original, c)) << c;
        EXPECT_EQ(copy.planes.at(c), original.planes.at(c)) << c;
    }
}

// Lossless compressions give back every value exactly. DWA is lossy for the channels OpenEXR
// classifies as colour (R, G, B, Y, any layer), half or float alike, and exact for A and depth.Z.
TEST(Exr, EveryCompressionRoundTrips) {
    const std::map<std::string, Imf::Compression> compressions{
        {"none", Imf::NO_COMPRESSION}, {"zip", Imf::ZIP_COMPRESSION},   {"zips", Imf::ZIPS_COMPRESSION},
        {"piz", Imf::PIZ_COMPRESSION}, {"dwaa", Imf::DWAA_COMPRESSION}, {"dwab", Imf::DWAB_COMPRESSION},
        {"rle", Imf::RLE_COMPRESSION}};
    ASSERT_EQ(knownCompressions().size(), compressions.size());
    const std::vector<AovSpec> aovs{{"direct", PixelType::Half}, {"transmittance", std::nullopt}, {"depth", std::nullopt}};
    for (const std::string& name : knownCompressions()) {
        SCOPED_TRACE(name);
        const std::string path = tempDir("exr_compression") + "/" + name + ".exr";
        writeExr(path, patternImage(), spec(PixelType::Float, name, aovs), ExrMetadata{});
        const Exr e = readExr(path);
        EXPECT_EQ(e.header.compression(), compressions.at(name));
        EXPECT_EQ(e.channels.size(), 9u);
        const bool dwa = name.starts_with("dwa");
        for (const auto& c : e.channels) {
            if (!dwa || c == "A" || c == "depth.Z") {
                expectPattern(e, c);
                continue;
            }
            // DWA at OpenEXR's default level (45) keeps these values within 0.02.
            float worst = 0.0f;
            for (size_t i = 0; i < e.planes.at(c).size(); ++i)
                worst = std::max(worst, std::abs(e.planes.at(c)[i] - expected(c)[i]));
            EXPECT_LT(worst, 0.02f) << c;
            EXPECT_GT(worst, 0.0f) << c << ": DWA stored the channel losslessly";
        }
    }
}

// Half layers saturate at 65504 and NaN becomes 0, both counted; a float layer keeps the value.
TEST(Exr, NonFiniteAndHalfOverflowAreCountedPerLayerType) {
    RenderImage img = patternImage();
    img.pixels[0].rgba.x = std::nanf("");
    img.pixels[1].direct.y = 70000.0f;
    img.pixels[1].emission.y = 70000.0f;
    const std::string path = tempDir("exr_overflow") + "/overflow.exr";
    const ExrWriteReport report = writeExr(
        path, img, spec(PixelType::Half, "zip", {{"direct", std::nullopt}, {"emission", PixelType::Float}}), ExrMetadata{});
    EXPECT_EQ(report.non_finite, 1u);
    EXPECT_EQ(report.half_overflow, 1u);
    const Exr e = readExr(path);
    EXPECT_EQ(e.planes.at("R")[0], 0.0f);
    EXPECT_EQ(e.planes.at("direct.G")[1], 65504.0f);
    EXPECT_EQ(e.planes.at("emission.G")[1], 70000.0f);
}

// A PNG as libpng's simplified API reads it, 8-bit samples in `format`; `format` in the result
// is the file's own.
struct Png {
    png_uint_32 width = 0, height = 0, format = 0;
    std::vector<png_byte> bytes;
};
Png readPng(const std::string& path, png_uint_32 format) {
    Png p;
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    EXPECT_TRUE(png_image_begin_read_from_file(&image, path.c_str())) << image.message;
    p.width = image.width;
    p.height = image.height;
    p.format = image.format;
    image.format = format;
    p.bytes.resize(PNG_IMAGE_SIZE(image));
    EXPECT_TRUE(png_image_finish_read(&image, nullptr, p.bytes.data(), 0, nullptr)) << image.message;
    return p;
}

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

TEST(Png, RoundTripClampsAndCountsNonFinite) {
    const float inf = std::numeric_limits<float>::infinity();
    // 3 x 2: in-range values, out-of-range ones and non-finite ones, alpha included.
    const std::vector<glm::vec4> rgba{{0.0f, 0.5f, 1.0f, 1.0f},     {0.2f, 0.4f, 0.6f, 0.8f},
                                      {-0.5f, 1.5f, 0.25f, 2.0f},   {std::nanf(""), inf, -inf, 0.5f},
                                      {0.001f, 0.999f, 0.75f, 0.0f}, {0.3f, 0.3f, 0.3f, std::nanf("")}};
    const std::string dir = tempDir("png");
    const PngWriteReport report = writePng(dir + "/rgba.png", 3, 2, rgba, true);
    EXPECT_EQ(report.non_finite, 4u);  // NaN, Inf, -Inf, NaN alpha
    EXPECT_EQ(report.clipped, 3u);     // -0.5, 1.5, alpha 2
    const Png p = readPng(dir + "/rgba.png", PNG_FORMAT_RGBA);
    EXPECT_EQ(p.width, 3u);
    EXPECT_EQ(p.height, 2u);
    EXPECT_EQ(p.format, png_uint_32(PNG_FORMAT_RGBA));
    const std::vector<png_byte> want{0,   128, 255, 255, 51, 102, 153, 204, 0,  255, 64,  255,
                                     0,   0,   0,   128, 0,  255, 191, 0,   77, 77,  77,  0};
    EXPECT_EQ(p.bytes, want);
    // Tagged as sRGB: an sRGB chunk (length 1, the rendering intent).
    EXPECT_NE(fileBytes(dir + "/rgba.png").find(std::string("\0\0\0\1sRGB", 8)), std::string::npos);

    // Without alpha the file is RGB and alpha is neither written nor counted.
    const PngWriteReport rgb = writePng(dir + "/rgb.png", 3, 2, rgba, false);
    EXPECT_EQ(rgb.non_finite, 3u);
    EXPECT_EQ(rgb.clipped, 2u);
    const Png q = readPng(dir + "/rgb.png", PNG_FORMAT_RGB);
    EXPECT_EQ(q.format, png_uint_32(PNG_FORMAT_RGB));
    EXPECT_EQ(q.bytes, (std::vector<png_byte>{0, 128, 255, 51, 102, 153, 0, 255, 64, 0, 0, 0, 0, 255, 191, 77, 77, 77}));
}

TEST(Png, WriteIntoAMissingFolderThrowsAndLeavesNothing) {
    const std::string dir = tempDir("png_missing");
    const std::string path = dir + "/missing/out.png";
    try {
        writePng(path, 1, 1, {glm::vec4(0.5f)}, false);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": cannot write in folder " + dir + "/missing: No such file or directory");
    }
    EXPECT_TRUE(fs::is_empty(dir));  // no file, no temporary, no folder
}

// A write that fails says what failed on the user's path, never the temporary's: the folder that
// cannot be made, the folder that takes no file, and why. outputProblem says the same without
// touching anything (--explain), and checkWritable before a run.
TEST(Exr, WriteErrorsNameTheFolderAndTheCause) {
    ReadOnlyFolder ro("write_errors_ro");
    if (!ro.problem.empty()) GTEST_SKIP() << ro.problem;
    const std::string in_ro = ro.path + "/out.exr", under_ro = ro.path + "/sub/out.exr";
    const std::string cannot_write = in_ro + ": cannot write in folder " + ro.path + ": " + ro.cause;
    const std::string cannot_create = under_ro + ": cannot create folder " + ro.path + "/sub: " + ro.cause;
    EXPECT_EQ(inputErrorOf([&] { writeExr(in_ro, patternImage(), spec(PixelType::Half, "zip", {}), ExrMetadata{}); }), cannot_write);
    EXPECT_EQ(inputErrorOf([&] { writeFileAtomically(in_ro, "{}\n"); }), cannot_write);
    EXPECT_EQ(inputErrorOf([&] { makeOutputFolder(under_ro); }), cannot_create);
    EXPECT_EQ(inputErrorOf([&] { checkWritable(under_ro); }), cannot_create);
    EXPECT_EQ(inputErrorOf([&] { checkWritable(in_ro); }), cannot_write);
    EXPECT_EQ(outputProblem(in_ro), cannot_write);
    EXPECT_EQ(outputProblem(under_ro), cannot_create);
    EXPECT_EQ(outputProblem(ro.path + "/a/b/c/out.exr"), ro.path + "/a/b/c/out.exr: cannot create folder " + ro.path + "/a/b/c: " + ro.cause);

    // A file where a folder must be; a writable folder has no problem, and checkWritable leaves it as it was.
    const std::string dir = tempDir("write_errors");
    std::ofstream(dir + "/a_file") << "x";
    EXPECT_EQ(outputProblem(dir + "/a_file/sub/out.exr"), dir + "/a_file/sub/out.exr: cannot create folder " + dir + "/a_file/sub: Not a directory");
    EXPECT_EQ(inputErrorOf([&] { checkWritable(dir + "/a_file/out.exr"); }),
              dir + "/a_file/out.exr: cannot create folder " + dir + "/a_file: Not a directory");
    EXPECT_EQ(outputProblem(dir + "/new/out.exr"), std::nullopt);
    EXPECT_FALSE(fs::exists(dir + "/new"));
    checkWritable(dir + "/new/out.exr");
    EXPECT_TRUE(fs::is_empty(dir + "/new"));
}

// The atomic write's rename once replaced /dev/null (as root) with a regular file. A device is
// written in place and stays a device; a full one gives the write's error; a folder is refused.
TEST(Exr, DevicesAreWrittenInPlaceAndFoldersRefused) {
    writeExr("/dev/null", patternImage(), spec(PixelType::Half, "zip", {}), ExrMetadata{});
    writeFileAtomically("/dev/null", "{}\n");
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    if (fs::exists("/dev/full")) {
        EXPECT_EQ(inputErrorOf([] { writeFileAtomically("/dev/full", "{}\n"); }), "/dev/full: cannot write (No space left on device)");
        EXPECT_TRUE(fs::is_character_file("/dev/full"));
    }
    const std::string dir = tempDir("write_folder");
    EXPECT_EQ(inputErrorOf([&] { writeFileAtomically(dir, "{}\n"); }), dir + ": is a folder, not a file");
    EXPECT_TRUE(fs::is_empty(dir));
}

// A killed render leaves ".out.exr.tmp-PID"; the next write of out.exr removes it when that
// process is gone, and leaves a running one's alone.
TEST(Exr, StaleTemporariesOfTheOutputAreRemoved) {
    const std::string dir = tempDir("stale_tmp");
    const std::string gone = dir + "/.out.exr.tmp-999999999", running = dir + "/.out.exr.tmp-1", other = dir + "/.other.exr.tmp-999999999";
    for (const std::string& f : {gone, running, other}) std::ofstream(f) << "partial";
    writeExr(dir + "/out.exr", patternImage(), spec(PixelType::Half, "zip", {}), ExrMetadata{});
    EXPECT_FALSE(fs::exists(gone));
    EXPECT_TRUE(fs::exists(running));   // pid 1 (init) always runs
    EXPECT_TRUE(fs::exists(other));     // another output's
    EXPECT_TRUE(fs::exists(dir + "/out.exr"));
}

// A data window beyond the 16384 pixels a side voxlux renders is refused before anything is
// allocated for it (fuzz_exr: a window of 30000 x 6 80-byte pixels in a 1 kB file).
TEST(Exr, AHugeDataWindowIsRefusedBeforeItIsAllocated) {
    const std::string dir = tempDir("huge_window");
    writeExr(dir + "/small.exr", patternImage(), spec(PixelType::Half, "zip", {}), ExrMetadata{});
    EXPECT_EQ(readExrRgba(dir + "/small.exr").width, patternImage().width);
    std::ifstream in(dir + "/small.exr", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string attribute("dataWindow\0box2i\0", 17);
    const size_t at = bytes.find(attribute);
    ASSERT_NE(at, std::string::npos);
    const int32_t xmax = 29999;   // after the attribute's size, xmin and ymin
    std::memcpy(bytes.data() + at + attribute.size() + 12, &xmax, sizeof xmax);
    std::ofstream(dir + "/huge.exr", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    const std::string error = inputErrorOf([&] { readExrRgba(dir + "/huge.exr"); });
    EXPECT_EQ(error.rfind(dir + "/huge.exr: cannot read EXR (", 0), 0u) << error;
    EXPECT_NE(error.find("16384"), std::string::npos) << error;
}

}  // namespace
}  // namespace voxlux::test
