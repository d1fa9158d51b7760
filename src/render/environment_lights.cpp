#include "render/environment_lights.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include "core/error.h"
#include "core/frame_pattern.h"
#include "grade/color_pipeline.h"
#include "io/exr_reader.h"
#include "optics/environment_map.h"
#include "optics/median_cut.h"
#include "volume/up_axis.h"
#include "volume/vdb_file.h"
#include "volume/vdb_loader.h"

namespace voxlux {

namespace {

// A map as read: working-space radiance, row 0 at the top, before orientation and scale; and the
// cuts made of it so far, in the map's own frame (up z, rotation 0).
struct ReadMap {
    int width = 0, height = 0;
    std::vector<glm::vec3> radiance;
    size_t repaired = 0;
    std::map<std::pair<int, bool>, MedianCut> cuts;   // by K and floor
    std::string oriented_key;                         // of the last oriented map
    std::shared_ptr<const EnvironmentMap> oriented;
};

// A file's identity: its path, size and modification time (equal identities, equal contents).
std::string fileKey(const std::string& path, std::error_code& ec) {
    const auto size = std::filesystem::file_size(path, ec);
    const auto time = ec ? std::filesystem::file_time_type{} : std::filesystem::last_write_time(path, ec);
    return path + "|" + std::to_string(size) + "|" + std::to_string(time.time_since_epoch().count());
}

// What identifies a read map: the file and the colour conversion.
std::string mapKey(const EnvironmentSettings& e, const ColorPipeline& working) {
    std::error_code ec;
    const std::string file = fileKey(e.map, ec);
    if (ec) throw InputError(e.map + ": cannot read the environment map (" + ec.message() + ")");
    return file + "|" + e.map_colorspace + "|" + working.config_source + "|" + working.working_space;
}

ReadMap readMap(const EnvironmentSettings& e, const ColorPipeline& working) {
    const RenderImage image = readExrRgba(e.map);
    if (image.pixels.empty()) throw InputError(e.map + ": an environment map needs pixels");
    ReadMap m;
    m.width = image.width;
    m.height = image.height;
    std::vector<glm::vec4> rgba(image.pixels.size());
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = glm::vec4(glm::vec3(image.pixels[i].rgba), 1.0f);
    const std::string from = requireColorSpace(*working.config, e.map_colorspace.empty() ? "scene_linear" : e.map_colorspace,
                                               "map_colorspace", working.config_source);
    try {
        OCIO::ConstCPUProcessorRcPtr cpu = working.config->getProcessor(from.c_str(), working.working_space.c_str())->getDefaultCPUProcessor();
        OCIO::PackedImageDesc desc(&rgba[0].x, long(rgba.size()), 1, 4);
        cpu->apply(desc);
    } catch (const OCIO::Exception& x) {
        throw InputError(e.map + ": cannot convert from '" + from + "' (" + x.what() + ")");
    }
    m.radiance.resize(rgba.size());
    for (size_t i = 0; i < rgba.size(); ++i) {
        // NaN or infinite: black; a negative channel (a colour conversion's overshoot): 0, the
        // others kept, so a sun whose blue dips below zero keeps its light.
        glm::vec3 c(rgba[i]);
        if (!std::isfinite(c.x + c.y + c.z)) {
            c = glm::vec3(0.0f);
            ++m.repaired;
        } else if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) {
            c = glm::max(c, glm::vec3(0.0f));
            ++m.repaired;
        }
        m.radiance[i] = c;
    }
    return m;
}

// The maps read in this process, by mapKey; a few, as a viewer switches between them.
class MapCache {
public:
    ReadMap& get(const EnvironmentSettings& e, const ColorPipeline& working) {
        const std::string key = mapKey(e, working);
        auto it = maps_.find(key);
        if (it == maps_.end()) {
            if (maps_.size() >= 4) maps_.clear();
            it = maps_.emplace(key, readMap(e, working)).first;
        }
        return it->second;
    }
    std::mutex mutex;

private:
    std::map<std::string, ReadMap> maps_;
};

MapCache& mapCache() {
    static MapCache cache;
    return cache;
}

std::shared_ptr<const EnvironmentMap> orientedMap(ReadMap& m, glm::vec3 up, float rotation, glm::vec3 scale) {
    // Exact: every float's bits.
    std::string key;
    for (float f : {up.x, up.y, up.z, rotation, scale.x, scale.y, scale.z}) {
        uint32_t bits = 0;
        std::memcpy(&bits, &f, sizeof bits);
        key += std::to_string(bits) + ",";
    }
    if (m.oriented && m.oriented_key == key) return m.oriented;
    std::vector<glm::vec3> radiance(m.radiance);
    for (glm::vec3& c : radiance) c *= scale;
    m.oriented = std::make_shared<const EnvironmentMap>(m.width, m.height, std::move(radiance), up, rotation);
    m.oriented_key = key;
    return m.oriented;
}

const MedianCut& cutOf(ReadMap& m, int lights, bool floor) {
    auto it = m.cuts.find({lights, floor});
    if (it == m.cuts.end()) {
        const EnvironmentMap own_frame(m.width, m.height, m.radiance, glm::vec3(0, 0, 1), 0.0f);
        it = m.cuts.emplace(std::make_pair(lights, floor), medianCut(own_frame, lights, floor)).first;
    }
    return it->second;
}

// The config and working space the maps are converted into: loaded once per config, working
// space and $OCIO, as a viewer sets its scene at every level of every edit.
const ColorPipeline& workingSpace(const ColorSettings& color) {
    static std::mutex mutex;
    static std::map<std::string, ColorPipeline> known;
    const char* ocio = std::getenv("OCIO");
    const std::string key = color.config + "|" + color.working_space + "|" + (ocio ? ocio : "");
    std::lock_guard<std::mutex> lock(mutex);
    auto it = known.find(key);
    if (it == known.end()) it = known.emplace(key, resolveWorkingSpace(color)).first;
    return it->second;
}

}  // namespace

glm::vec3 defaultEnvironmentUp(const Scene& scene) {
    const VolumeSpec& v = scene.volume();
    int axis = 1;
    if (v.up != UpAxis::Auto) {
        axis = int(v.up) - int(UpAxis::X);
    } else if (!v.path.empty() && (!hasFramePattern(v.path) || v.frames)) {
        // Read once per file: a viewer sets its scene at every level of every edit.
        static std::mutex mutex;
        static std::map<std::string, int> axes;   // by the file's identity
        const std::string path = v.frames ? expandFramePattern(v.path, v.frames->first()) : v.path;
        std::error_code ec;
        const std::string key = fileKey(path, ec);
        std::lock_guard<std::mutex> lock(mutex);
        const auto known = axes.find(key);
        if (known != axes.end()) return glm::vec3(known->second == 0, known->second == 1, known->second == 2);
        try {
            initOpenVdb();
            VdbFile file(path);
            // The density grid's metadata too, as the load reads it (a Mantaflow cache says z there).
            openvdb::MetaMap grid;
            for (size_t k = 0, seen = 0; k < file.grids().size(); ++k)
                if (file.grids()[k].name == v.density.name && int(seen++) == v.density.index) grid = file.gridMetadata(k);
            axis = detectUpAxis(file.fileMetadata(), grid).axis;
            axes[key] = axis;
        } catch (const InputError&) {
            // The volume's load names the file's problem.
        }
    }
    return glm::vec3(axis == 0, axis == 1, axis == 2);
}

Scene withEnvironmentLights(Scene scene) {
    std::erase_if(scene.lights, [](const Light& l) { return l.from_environment.has_value(); });   // made again below
    const bool any = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.environment.has_value(); });
    if (!any) return scene;
    const ColorPipeline& working = workingSpace(scene.color);
    const bool reference = scene.render.method == RenderMethod::Reference;
    std::optional<glm::vec3> default_up;
    std::lock_guard<std::mutex> lock(mapCache().mutex);
    std::vector<Light> parts;   // appended after the scene's own
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        Light& light = scene.lights[i];
        if (!light.environment || !light.enabled) continue;
        EnvironmentSettings& e = *light.environment;
        if (!e.up && !default_up) default_up = defaultEnvironmentUp(scene);
        const glm::vec3 up = e.up.value_or(*default_up);
        ReadMap& m = mapCache().get(e, working);
        e.loaded = orientedMap(m, up, e.rotation, light.color * light.intensity);
        e.repaired_pixels = m.repaired;
        if (reference) continue;
        const MedianCut& cut = cutOf(m, e.median_cut_lights, e.remainder == EnvironmentRemainder::Floor);
        const glm::mat3 frame = environmentFrame(up, e.rotation);
        Light part;
        part.group = light.group;
        part.from_environment = i;
        part.intensity = light.intensity;
        for (const CutLight& c : cut.lights) {
            if (!(c.irradiance.x + c.irradiance.y + c.irradiance.z > 0.0f)) continue;
            part.type = LightType::Directional;
            part.direction = -(frame * c.toward);
            part.color = c.irradiance * light.color;
            parts.push_back(part);
        }
        if (cut.ambient.x + cut.ambient.y + cut.ambient.z > 0.0f) {
            part.type = LightType::Ambient;
            part.color = cut.ambient * light.color;
            parts.push_back(part);
        }
    }
    scene.lights.insert(scene.lights.end(), parts.begin(), parts.end());
    return scene;
}

}  // namespace voxlux
