// The registry of lighting methods: one line a method (its folder's registration function).
#include "lighting/lighting_method.h"

#include <stdexcept>

#include "lighting/extinction_sat/extinction_sat_method.h"
#include "lighting/propagation/propagation_method.h"

namespace voxlux {
namespace {

std::vector<LightingMethodEntry>& registry() {
    static std::vector<LightingMethodEntry> methods = {
        {"extinction_sat", makeExtinctionSatMethod},
        {"propagation", makePropagationMethod},
    };
    return methods;
}

}  // namespace

void unregisterLightingMethod(const std::string& name) {
    std::erase_if(registry(), [&](const LightingMethodEntry& m) { return m.name == name; });
}

const std::vector<LightingMethodEntry>& lightingMethods() { return registry(); }

void registerLightingMethod(LightingMethodEntry method) {
    for (const LightingMethodEntry& m : registry())
        if (m.name == method.name) throw std::logic_error("lighting method " + method.name + " is registered already");
    registry().push_back(std::move(method));
}

}  // namespace voxlux
