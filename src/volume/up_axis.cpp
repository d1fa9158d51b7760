#include "volume/up_axis.h"

namespace voxlux {
namespace {

std::string creatorOf(const openvdb::MetaMap& m) {
    const auto c = m.getMetadata<openvdb::StringMetadata>("creator");
    return c ? c->value() : std::string();
}

std::string stringOf(const openvdb::MetaMap& m, const std::string& key) {
    const auto c = m.getMetadata<openvdb::StringMetadata>(key);
    return c ? c->value() : std::string();
}

UpAxisGuess along(int axis, std::string reason) { return {axis, std::move(reason), upFrame(axis)}; }

int axisIndex(glm::vec3 axis) { return axis.x != 0.0f ? 0 : axis.y != 0.0f ? 1 : 2; }

}  // namespace

glm::mat3 upFrame(int up_axis) {
    switch (up_axis) {
        case 0: return {glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, -1)};
        case 2: return {glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, -1, 0)};
        default: return glm::mat3(1.0f);
    }
}

std::optional<glm::vec3> parseSignedAxis(const std::string& text) {
    const bool negative = !text.empty() && text[0] == '-';
    const std::string name = negative ? text.substr(1) : text;
    if (name != "x" && name != "y" && name != "z") return std::nullopt;
    glm::vec3 axis(0.0f);
    axis[name[0] - 'x'] = negative ? -1.0f : 1.0f;
    return axis;
}

std::string signedAxisName(glm::vec3 axis) {
    const int a = axisIndex(axis);
    return std::string(axis[a] < 0.0f ? "-" : "") + char('x' + a);
}

glm::mat3 viewFrame(glm::vec3 up, glm::vec3 front) { return {glm::cross(up, front), up, front}; }

UpAxisGuess detectUpAxis(const openvdb::MetaMap& file_metadata, const openvdb::MetaMap& grid_metadata) {
    const auto up = parseSignedAxis(stringOf(grid_metadata, "up_axis")), front = parseSignedAxis(stringOf(grid_metadata, "front_axis"));
    if (up && front && glm::dot(*up, *front) == 0.0f)
        return {axisIndex(*up), signedAxisName(*up) + " (the grid's up_axis metadata; its front_axis " + signedAxisName(*front) + " faces the camera)",
                viewFrame(*up, *front)};
    std::string creator = creatorOf(grid_metadata);
    if (creator.empty()) creator = creatorOf(file_metadata);
    if (grid_metadata["file_base_resolution"])
        return along(2, "z (a Blender Mantaflow cache: grids carry file_base_resolution)");
    if (creator.rfind("Blender", 0) == 0) return along(2, "z (creator '" + creator + "')");
    const auto local = grid_metadata.getMetadata<openvdb::BoolMetadata>("is_local_space");
    if (creator.empty() && local && local->value())
        return along(2, "z (a grid in local space with no creator, as Blender's smoke cache saves it)");
    if (!creator.empty()) return along(1, "y (creator '" + creator + "')");
    return along(1, "y (the file does not say; OpenVDB's convention)");
}

}  // namespace voxlux
