#include "volume/vdb_loader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>

#include <openvdb/util/logging.h>

#include <openvdb/tools/GridTransformer.h>
#include <openvdb/tools/LevelSetUtil.h>

#include "volume/brick_set.h"
#include "volume/vdb_file.h"
#include "volume/velocity.h"
#include "core/error.h"
#include "kernel/kernel_types.h"
#include "scene/camera.h"

namespace voxlux {
namespace {

std::string describe(const std::string& name, const std::string& value_type) {
    return "'" + printableName(name) + "' (" + value_type + ")";
}
std::string describe(const openvdb::GridBase& g) { return describe(g.getName(), g.valueType()); }

// Opens `file` or throws a one-line InputError.
VdbFile openFile(const std::string& file) {
    if (!std::filesystem::exists(file)) throw InputError(file + ": no such file");
    return VdbFile(file);
}

// `option` names the flag that picks the grid ("--grid"), for the hint of a missing one.
openvdb::GridBase::Ptr readGrid(VdbFile& f, const std::string& file, const GridRef& ref,
                                std::vector<std::string>& warnings, const std::string& option = "") {
    std::vector<size_t> named;
    for (size_t k = 0; k < f.grids().size(); ++k)
        if (f.grids()[k].name == ref.name) named.push_back(k);
    const int count = int(named.size());
    if (count == 0) throw InputError(f.noGridNamed(ref.name, option));
    if (ref.index >= count)
        throw InputError(file + ": grid index " + std::to_string(ref.index) + " for '" + ref.name +
                         "' is out of range (the file has " + std::to_string(count) + ")");
    if (count > 1)
        warnings.push_back(file + ": " + std::to_string(count) + " grids are named '" + ref.name +
                           "'; using index " + std::to_string(ref.index) + " (set the grid's \"index\" to choose)");
    return f.read(named[size_t(ref.index)]);
}

// A scalar grid as float, with level sets rejected or converted as the spec says.
openvdb::FloatGrid::Ptr asFogFloat(openvdb::GridBase::Ptr g, const std::string& file, const VolumeSpec& spec,
                                   const std::string& role) {
    openvdb::FloatGrid::Ptr out;
    if (auto f = openvdb::GridBase::grid<openvdb::FloatGrid>(g)) {
        out = f;
    } else if (auto d = openvdb::GridBase::grid<openvdb::DoubleGrid>(g)) {
        out = openvdb::FloatGrid::create(openvdb::FloatTree::Ptr(new openvdb::FloatTree(d->tree())));
        out->setTransform(d->transform().copy());
        out->setGridClass(d->getGridClass());
        out->setName(d->getName());
    } else {
        throw InputError(file + ": grid " + describe(*g) + " cannot be used as " + role +
                         " (it needs float or double values)");
    }
    if (out->getGridClass() == openvdb::GRID_LEVEL_SET) {
        if (spec.level_set == LevelSetPolicy::Reject)
            throw InputError(file + ": grid '" + out->getName() + "' is a level set, not a fog volume; "
                             "set volume.level_set to \"fog\" (or pass --level-set fog) to convert it");
        openvdb::tools::sdfToFogVolume(*out);
    }
    return out;
}

openvdb::Vec3SGrid::Ptr asVector(openvdb::GridBase::Ptr g, const std::string& file, const std::string& role) {
    if (auto v = openvdb::GridBase::grid<openvdb::Vec3SGrid>(g)) return v;
    if (auto d = openvdb::GridBase::grid<openvdb::Vec3DGrid>(g)) {
        auto out = openvdb::Vec3SGrid::create(openvdb::Vec3STree::Ptr(new openvdb::Vec3STree(d->tree())));
        out->setTransform(d->transform().copy());
        out->setName(d->getName());
        return out;
    }
    throw InputError(file + ": grid " + describe(*g) + " cannot be used as " + role + " (it needs vec3 values)");
}

// Emission and colour grids are resampled onto the density grid's index space when they differ.
template <typename GridT>
typename GridT::Ptr matchTransform(typename GridT::Ptr g, const openvdb::FloatGrid& density,
                                   const std::string& file, std::vector<std::string>& warnings) {
    if (g->transform() == density.transform()) return g;
    warnings.push_back(file + ": grid '" + g->getName() + "' has a different transform from '" +
                       density.getName() + "'; resampled onto it");
    auto out = GridT::create(g->background());
    out->setTransform(density.transform().copy());
    out->setName(g->getName());
    openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*g, *out);
    return out;
}

// The range of a grid's active values (of their lengths for vectors); false for other types.
bool activeValueRange(const openvdb::GridBase& g, double& lo, double& hi, bool& vector) {
    lo = INFINITY, hi = -INFINITY;
    const auto scan = [&](const auto& grid, auto value_of) {
        for (auto it = grid.cbeginValueOn(); it; ++it) {
            const double v = value_of(*it);
            lo = std::min(lo, v), hi = std::max(hi, v);
        }
        return true;
    };
    const auto scalar = [](auto v) { return double(v); };
    const auto length = [](const auto& v) { return double(v.length()); };
    vector = false;
    if (g.isType<openvdb::FloatGrid>()) return scan(static_cast<const openvdb::FloatGrid&>(g), scalar);
    if (g.isType<openvdb::DoubleGrid>()) return scan(static_cast<const openvdb::DoubleGrid&>(g), scalar);
    if (g.isType<openvdb::Int32Grid>()) return scan(static_cast<const openvdb::Int32Grid&>(g), scalar);
    if (g.isType<openvdb::Int64Grid>()) return scan(static_cast<const openvdb::Int64Grid&>(g), scalar);
    vector = true;
    if (g.isType<openvdb::Vec3SGrid>()) return scan(static_cast<const openvdb::Vec3SGrid&>(g), length);
    if (g.isType<openvdb::Vec3DGrid>()) return scan(static_cast<const openvdb::Vec3DGrid&>(g), length);
    vector = false;
    return false;
}

// OpenVDB writes file_bbox_min/max from the tree when it saves a grid; a file whose metadata says
// otherwise was altered or damaged after it was written. voxlux reads the tree, never these.
std::string bboxMetadataMismatch(const openvdb::GridBase& g, const openvdb::CoordBBox& tree_box) {
    const auto lo = g.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MIN);
    const auto hi = g.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MAX);
    if (!lo || !hi) return "";
    const openvdb::CoordBBox claimed(openvdb::Coord(lo->value()), openvdb::Coord(hi->value()));
    if (claimed == tree_box) return "";
    const auto text = [](const openvdb::Coord& c) {
        return "[" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) + "]";
    };
    return "file_bbox " + text(claimed.min()) + " -> " + text(claimed.max()) + " but the voxels' bbox is " +
           (tree_box.empty() ? std::string("empty") : text(tree_box.min()) + " -> " + text(tree_box.max())) +
           " (the metadata is ignored)";
}

// The velocity grid motion blur reads: the one it names, else the first of velocityGridNames()
// the file has, else none.
std::optional<GridRef> velocityGrid(const VdbFile& f, const MotionBlur& motion) {
    if (motion.velocity) return motion.velocity;
    for (const auto& name : velocityGridNames())
        for (const auto& grid : f.grids())
            if (grid.name == name) return GridRef{name, 0};
    return std::nullopt;
}

std::string joinedVelocityNames() {
    std::string out;
    for (const auto& name : velocityGridNames()) out += (out.empty() ? "looked for " : ", ") + name;
    return out;
}

}  // namespace

void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] {
        openvdb::initialize();
        // voxlux reports what matters itself, one line each; OpenVDB's own warnings would repeat it.
        openvdb::logging::setLevel(openvdb::logging::Level::Error);
    });
}

float voxelEdge(const glm::mat4& m) {
    return std::min({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
}

void voxelBoxWorldBounds(const glm::mat4& index_to_world, const openvdb::CoordBBox& box, glm::vec3& lo, glm::vec3& hi) {
    worldBounds(index_to_world, glm::vec3(box.min().x(), box.min().y(), box.min().z()),
                glm::vec3(box.max().x(), box.max().y(), box.max().z()), lo, hi);
}

glm::mat4 indexToWorld(const openvdb::GridBase& grid, const std::string& file) {
    const auto& map = *grid.transform().baseMap();
    if (!map.isLinear())
        throw InputError(file + ": grid '" + grid.getName() + "' has a non-affine (" + map.type() +
                         ") transform, which voxlux does not support");
    // Built from the map's images of the origin and the unit axes: getAffineMap() of a singular
    // map throws from a noexcept path in OpenVDB and aborts (fuzz_vdb found a zero scale).
    const openvdb::Vec3d origin = map.applyMap(openvdb::Vec3d(0.0));
    glm::mat4 out(1.0f);
    for (int c = 0; c < 3; ++c) {
        openvdb::Vec3d axis(0.0);
        axis[c] = 1.0;
        const openvdb::Vec3d image = map.applyMap(axis) - origin;
        out[c] = glm::vec4(float(image[0]), float(image[1]), float(image[2]), 0.0f);
    }
    out[3] = glm::vec4(float(origin[0]), float(origin[1]), float(origin[2]), 1.0f);
    const float det = glm::determinant(out);
    if (!(std::isfinite(det) && det != 0.0f) || !std::isfinite(out[3].x + out[3].y + out[3].z))
        throw InputError(file + ": grid '" + grid.getName() + "' has a singular index-to-world transform");
    return out;
}

namespace {

// The default view's frame (right, up, back) turned as `linear` places the volume, kept orthonormal.
glm::mat3 placedFrame(const glm::mat3& linear, const glm::mat3& frame) {
    const glm::vec3 up = glm::normalize(linear * frame[1]);
    glm::vec3 back = linear * frame[2];
    back = glm::normalize(back - glm::dot(back, up) * up);
    return glm::mat3(glm::cross(up, back), up, back);
}

}  // namespace

LoadedVolume placedVolume(LoadedVolume v, const glm::mat4& placement) {
    if (placement == glm::mat4(1.0f)) return v;
    v.index_to_world = placement * v.index_to_world;
    v.up.frame = placedFrame(glm::mat3(placement), v.up.frame);
    const glm::vec3 up = glm::abs(v.up.frame[1]);
    v.up.axis = up.x >= up.y && up.x >= up.z ? 0 : up.y >= up.z ? 1 : 2;
    v.up.reason += ", turned by volume.transform";
    return v;
}

LoadedVolume loadVolume(const std::string& file, const VolumeSpec& spec, const std::optional<MotionBlur>& motion) {
    initOpenVdb();
    VdbFile f = openFile(file);
    LoadedVolume v;
    v.file = file;
    auto density = asFogFloat(readGrid(f, file, spec.density, v.warnings, "--grid"), file, spec, "density");
    v.index_to_world = indexToWorld(*density, file);
    v.up = detectUpAxis(f.fileMetadata(), *density);
    for (const auto& source : spec.emission)
        v.emission.push_back(matchTransform<openvdb::FloatGrid>(
            asFogFloat(readGrid(f, file, source.grid, v.warnings), file, spec, "emission"), *density, file,
            v.warnings));
    if (spec.color)
        v.color = matchTransform<openvdb::Vec3SGrid>(asVector(readGrid(f, file, *spec.color, v.warnings), file, "colour"),
                                                     *density, file, v.warnings);
    if (motion) {
        if (std::optional<GridRef> ref = velocityGrid(f, *motion)) {
            const auto velocity = matchTransform<openvdb::Vec3SGrid>(
                velocityAtVoxelCentres(asVector(readGrid(f, file, *ref, v.warnings), file, "velocity")), *density, file, v.warnings);
            v.max_speed = maxSpeed(*velocity);
            const float reach = motionReachVoxels(v.max_speed, voxelEdge(v.index_to_world), *motion, file, velocity->getName());
            extendVelocity(*velocity, int(std::ceil(reach)));
            v.velocity = velocity;
        } else {
            v.warnings.push_back(file + ": no velocity grid (" + joinedVelocityNames() + "; grids: " + f.gridList() +
                                 "); only a moving camera blurs (set render.motion_blur.velocity to name one)");
        }
    }
    v.density = density;
    return v;
}

std::vector<GridSummary> summarizeFile(const std::string& file) {
    initOpenVdb();
    VdbFile f = openFile(file);
    std::vector<GridSummary> out;
    for (size_t k = 0; k < f.grids().size(); ++k) {
        if (!f.grids()[k].volume) {   // listed, not read
            GridSummary listed;
            listed.name = f.grids()[k].name;
            listed.value_type = f.grids()[k].value_type;
            listed.grid_class = "points (not read)";
            out.push_back(listed);
            continue;
        }
        const openvdb::GridBase::Ptr g = f.read(k);
        GridSummary s;
        s.name = g->getName();
        s.value_type = g->valueType();
        s.grid_class = openvdb::GridBase::gridClassToString(g->getGridClass());
        s.active_voxels = g->activeVoxelCount();
        s.active_tiles = g->baseTree().activeTileCount();
        s.bbox = g->evalActiveVoxelBoundingBox();
        s.damaged_metadata = bboxMetadataMismatch(*g, s.bbox);
        s.voxel_size = g->voxelSize();
        s.bricks = countBricks(*g);
        s.brick_bytes = s.bricks * VX_BRICK_VOXELS * sizeof(float);
        s.up = detectUpAxis(f.fileMetadata(), *g);
        for (const auto& earlier : out) s.index += earlier.name == s.name;
        if (s.active_voxels > 0) {
            s.has_range = activeValueRange(*g, s.min_value, s.max_value, s.vector);
            voxelBoxWorldBounds(indexToWorld(*g, file), s.bbox, s.world_min, s.world_max);
        }
        out.push_back(s);
    }
    return out;
}

}  // namespace voxlux
