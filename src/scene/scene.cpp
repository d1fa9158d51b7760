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

const std::vector<std::string>& knownCompressions() {
    static const std::vector<std::string> names{"none", "zip", "zips", "piz", "dwaa", "dwab", "rle"};
    return names;
}

}  // namespace voxlux
