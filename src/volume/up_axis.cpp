#include "volume/up_axis.h"

namespace voxlux {
namespace {

std::string creatorOf(const openvdb::MetaMap& m) {
    const auto c = m.getMetadata<openvdb::StringMetadata>("creator");
    return c ? c->value() : std::string();
}

}  // namespace

UpAxisGuess detectUpAxis(const openvdb::MetaMap& file_metadata, const openvdb::MetaMap& grid_metadata) {
    std::string creator = creatorOf(grid_metadata);
    if (creator.empty()) creator = creatorOf(file_metadata);
    if (grid_metadata["file_base_resolution"])
        return {2, "z (a Blender Mantaflow cache: grids carry file_base_resolution)"};
    if (creator.rfind("Blender", 0) == 0) return {2, "z (creator '" + creator + "')"};
    const auto local = grid_metadata.getMetadata<openvdb::BoolMetadata>("is_local_space");
    if (creator.empty() && local && local->value())
        return {2, "z (a grid in local space with no creator, as Blender's smoke cache saves it)"};
    if (!creator.empty()) return {1, "y (creator '" + creator + "')"};
    return {1, "y (the file does not say; OpenVDB's convention)"};
}

}  // namespace voxlux
