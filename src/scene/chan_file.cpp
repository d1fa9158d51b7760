#include "scene/chan_file.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/json_reader.h"

namespace voxlux {
namespace {

constexpr double kMaxChanValue = 1e9;   // as a scene's world coordinates

// The whitespace-separated fields of one line.
std::vector<std::string_view> fields(std::string_view line) {
    std::vector<std::string_view> out;
    size_t k = 0;
    while (k < line.size()) {
        while (k < line.size() && std::isspace(static_cast<unsigned char>(line[k]))) ++k;
        const size_t start = k;
        while (k < line.size() && !std::isspace(static_cast<unsigned char>(line[k]))) ++k;
        if (k > start) out.push_back(line.substr(start, k - start));
    }
    return out;
}

}  // namespace

ChanTrack parseChan(const std::string& text, const std::string& file) {
    ChanTrack track;
    std::vector<TransformKey>& keys = track.keys;
    std::istringstream lines(text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        const auto fail = [&](const std::string& problem) {
            throw InputError(file + ": line " + std::to_string(number) + ": " + problem);
        };
        const std::vector<std::string_view> f = fields(line);
        if (f.empty()) continue;
        if (f.size() != 7 && f.size() != 8)
            fail("expected frame tx ty tz rx ry rz (7 numbers, or 8 from a camera), found " + std::to_string(f.size()) + " fields");
        double v[8];
        for (size_t i = 0; i < f.size(); ++i) {
            const char* end = f[i].data() + f[i].size();
            const auto [stop, error] = std::from_chars(f[i].data(), end, v[i]);
            if (error != std::errc() || stop != end || !std::isfinite(v[i]))
                fail(jsonText(std::string(f[i])) + " is not a finite number");
            if (std::abs(v[i]) > kMaxChanValue) fail("value " + std::string(f[i]) + " lies beyond +-1e9");
        }
        if (!keys.empty() && !(v[0] > keys.back().frame))
            fail("frame " + std::string(f[0]) + " does not follow frame " + jsonText(keys.back().frame) + " (frames must increase)");
        if (f.size() == 8 && !(v[7] > 0.0 && v[7] < 180.0)) fail("field of view " + std::string(f[7]) + " does not lie in (0, 180) degrees");
        keys.push_back({v[0], glm::vec3(v[1], v[2], v[3]), glm::vec3(v[4], v[5], v[6]), glm::vec3(1.0f)});
        if (f.size() == 8) track.vertical_fov.push_back(float(v[7]));
    }
    if (keys.empty()) throw InputError(file + ": no keys (expected lines of frame tx ty tz rx ry rz)");
    if (track.vertical_fov.size() != keys.size()) track.vertical_fov.clear();   // a lens only where every key has one
    return track;
}

ChanTrack readChanFile(const std::string& path) { return parseChan(readFileText(path, ".chan file"), path); }

}  // namespace voxlux
