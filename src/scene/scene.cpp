// What the scene model answers about itself (scene.h).
#include <algorithm>

#include "scene/scene.h"

namespace voxlux {

int enabledLightCount(const Scene& scene, bool ambient) {
    return int(std::count_if(scene.lights.begin(), scene.lights.end(),
                             [&](const Light& l) { return l.enabled && (l.type == LightType::Ambient) == ambient; }));
}

const std::vector<std::string>& knownAovs() {
    static const std::vector<std::string> aovs{"direct", "ambient", "indirect", "emission", "transmittance", "depth", "variance"};
    return aovs;
}

std::string deepPath(const std::string& output_path) {
    const size_t dot = output_path.size() >= 4 ? output_path.size() - 4 : 0;   // ".exr", in any case (scene_read.cpp checks)
    return output_path.substr(0, dot) + ".deep" + output_path.substr(dot);
}

const std::vector<std::string>& knownCompressions() {
    static const std::vector<std::string> names{"none", "zip", "zips", "piz", "dwaa", "dwab", "rle"};
    return names;
}

}  // namespace voxlux
