// A lighting method as one unit, as Mitsuba's plugins and pbrt-v4's media are: the stages it adds
// to the render graph, those of them whose outputs the march reads, and what its light update did
// in a frame. Each method's folder has one registration file (<method>/<method>_method.cpp) that
// makes it from the shared stages; src/lighting/lighting_methods.cpp lists the methods, and a
// test may add its own (registerLightingMethod). The renderer builds every registered method's
// stages; a scene that does not use a method skips them (their activity says why).
// Cost: none; the stages are the methods'.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "graph/render_graph.h"
#include "lighting/light_update.h"

namespace voxlux {

class BrickStage;
class CameraStage;
class ClassifyStage;
class LightGridStage;
class VolumesStage;
class MarchLightingStage;

// The stages before the lighting that a method's stages may read.
struct SharedStages {
    const Stage& color_space;                    // a stage of a higher layer (grade), read through:
    std::function<glm::mat3()> xyz_to_working;   // its CIE XYZ -> working-space matrix
    const BrickStage& brick;
    const ClassifyStage& classify;
    const VolumesStage& volumes;                 // of several volumes, their joined bricks
    const CameraStage& camera;
    LightGridStage& light_grid;                  // a method that reads it adds itself as a reader
};

class LightingMethod {
public:
    virtual ~LightingMethod() = default;
    // Its stages (owned by the method), each after those it reads.
    virtual std::vector<Stage*> stages() = 0;
    // Those the march reads, in the order they set its sources (MarchLightingStage).
    virtual std::vector<const MarchLightingStage*> marchInputs() const = 0;
    // What its light update did in the frame whose stage reports are `frame`, if it has one.
    virtual std::optional<LightUpdate> lightUpdate(const std::vector<StageReport>& /* frame */) const { return std::nullopt; }
};

struct LightingMethodEntry {
    std::string name;   // its folder under src/lighting/
    std::function<std::unique_ptr<LightingMethod>(const SharedStages&)> make;
};

// The registered methods, in the order the renderer makes them.
const std::vector<LightingMethodEntry>& lightingMethods();

// Adds `method` to the registry (a method defined outside src/lighting/, as a test's): renderers
// made afterwards build its stages too. Throws std::logic_error when its name is taken.
void registerLightingMethod(LightingMethodEntry method);
// Takes the method named `name` out of the registry (a test's, when the test ends).
void unregisterLightingMethod(const std::string& name);

}  // namespace voxlux
