#include "volume/volume_stages.h"

#include <algorithm>
#include <limits>

#include "optics/transfer_function_2d.h"
#include "scene/camera.h"
#include "scene/camera_file.h"
#include "scene/scene_json.h"
#include "volume/mesh_voxels.h"
#include "volume/transfer_2d.h"
#include "volume/velocity.h"
#include "core/error.h"

namespace voxlux {
namespace {

std::string nothingVisible(const LoadedVolume& v, const BrickAtlas& atlas, const Scene& scene) {
    std::string grid = "grid '" + v.density->getName() + "'";
    if (!scene.volume().material.transfer_2d.empty() && atlas.active_voxels == 0)
        return v.file + ": the 2D transfer function selects none of " + grid + "'s voxels (material.transfer_function_2d)";
    if (atlas.active_voxels == 0) return v.file + ": " + grid + " has no active voxels";
    std::string why = v.file + ": " + grid + " has nothing visible: its " + std::to_string(atlas.active_voxels) +
                      " active voxels are all zero";
    if (atlas.density_fixes.negative) why += " or negative (" + std::to_string(atlas.density_fixes.negative) + " negative)";
    why += " under the material";
    for (size_t e = 0; e < v.emission.size(); ++e) why += (e ? ", '" : "; emission from '") + v.emission[e]->getName() + "'";
    return why + (v.emission.empty() ? "" : " emits nothing");
}

}  // namespace

StageReads LoadStage::reads() const {
    return {{"/input/file", "/volumes/*/path", "/volumes/*/density", "/volumes/*/color", "/volumes/*/level_set", "/volumes/*/emission/*/grid",
             "/render/motion_blur?", "/render/motion_blur/velocity", "/render/motion_blur/shutter", "/render/motion_blur/velocity_scale",
             "/render/motion_blur/fps"}};
}

StageActivity LoadStage::activity(const Scene& s) const {
    std::string grids = "density '" + s.volume().density.name + "'";
    if (s.volume().color) grids += ", colour '" + s.volume().color->name + "'";
    for (size_t i = 0; i < s.volume().emission.size(); ++i) grids += (i ? ", '" : ", emission '") + s.volume().emission[i].grid.name + "'";
    if (const auto& mb = s.render.motion_blur) {
        std::string names;
        for (const auto& name : velocityGridNames()) names += (names.empty() ? "" : ", ") + name;
        grids += mb->velocity ? ", velocity '" + mb->velocity->name + "'" : ", velocity (the first of " + names + ")";
    }
    return {true, "reads " + grids + " from " + (given_ ? "grids in memory" : s.volume().path)};
}

void LoadStage::run(StageRun& run) {
    const Scene& scene = run.scene({"/volumes/*/path", "/volumes/*/density", "/volumes/*/color", "/volumes/*/level_set",
                                    "/volumes/*/emission/*/grid", "/render/motion_blur"});
    volume_ = std::make_shared<const LoadedVolume>(
        given_ ? *given_ : loadVolume(run.scene.value("/input/file/path"), scene.volume(), scene.render.motion_blur));
    run.warnings = volume_->warnings;
}

namespace {

size_t gridBytes(const std::shared_ptr<const LoadedVolume>& volume) {
    if (!volume) return 0;
    size_t bytes = volume->density->memUsage() + (volume->color ? volume->color->memUsage() : 0) +
                   (volume->velocity ? volume->velocity->memUsage() : 0);
    for (const auto& grid : volume->emission) bytes += grid->memUsage();
    return bytes;
}

}  // namespace

size_t LoadStage::outputBytes() const { return gridBytes(volume_); }

// Only the classified grids: the others are load's.
size_t Transfer2dStage::outputBytes() const {
    if (!volume_) return 0;
    return volume_->density->memUsage() + volume_->color->memUsage() + (volume_->transport ? volume_->transport->memUsage() : 0) +
           (volume_->surface ? volume_->surface->memUsage() : 0);
}

StageActivity Transfer2dStage::activity(const Scene& s) const {
    if (s.volume().material.transfer_2d.empty()) return {false, "skipped: no 2D transfer function (material.transfer_function_2d)"};
    return {true, std::string("classifies each voxel by value and gradient magnitude into extinction, albedo") +
                      (regionsCarryTransport(s.volume().material.transfer_2d) ? ", transport colour" : "") +
                      (regionsCarrySurface(s.volume().material.transfer_2d) ? ", surface weight" : "") + " (" +
                      std::to_string(s.volume().material.transfer_2d.size()) + " regions, Kniss 2002)"};
}

void Transfer2dStage::run(StageRun& run) {
    volume_ = std::make_shared<const LoadedVolume>(applyTransfer2d(load_.volume(), run.scene({"/volumes/*/material/transfer_function_2d"}).volume().material.transfer_2d, run.warnings));
}

StageReads BrickStage::reads() const {
    return {{"/render/motion_blur?", "/render/motion_blur/shutter", "/render/motion_blur/velocity_scale", "/render/motion_blur/fps"}};
}

StageActivity BrickStage::activity(const Scene& s) const {
    return {true, std::string("densifies active voxels into 8^3 bricks with a +1 apron") +
                      (s.render.motion_blur ? "; and the velocity, over the bricks the blurred medium can reach" : "")};
}

void BrickStage::run(StageRun& run) {
    const LoadedVolume& volume = load_.volume();
    atlas_ = std::make_shared<const BrickAtlas>(buildBrickAtlas(volume, motionReachBricks(volume, run.scene({"/render/motion_blur"}).render.motion_blur)));
    run.warnings = sanitizeReport(*atlas_, load_.volume());
}

StageReads ClassifyStage::reads() const { return {{"/volumes/*/material", "/volumes/*/emission", "/render/filter"}}; }

StageActivity ClassifyStage::activity(const Scene& s) const {
    std::string what = !s.volume().material.transfer.empty()    ? "drops bricks the transfer function makes transparent"
                       : !s.volume().material.transfer_2d.empty() ? "drops bricks the 2D transfer function selects nothing in"
                                                          : "drops bricks with zero density and emission";
    if (s.render.motion_blur) what += "; keeps the bricks the blurred medium can reach";
    if (s.render.filter == Filter::Tricubic) what += "; keeps the neighbours of visible ones, which the tricubic filter reads";
    return {true, what};
}

void ClassifyStage::run(StageRun& run) {
    const BrickAtlas& atlas = brick_.atlas();
    const Scene& scene = run.scene({"/volumes/*/material", "/volumes/*/emission", "/render/filter"});
    pages_ = classifiedPageTable(atlas, scene);
    empty_reason_ = pages_.empty() ? nothingVisible(load_.volume(), atlas, scene) : "";
}

StageActivity EmptyFrameStage::activity(const Scene&) const {
    return {true, "refuses a frame with nothing visible, unless a sequence allows empty frames"};
}

void EmptyFrameStage::run(StageRun& run) {
    if (classify_.emptyReason().empty() || !noVisibleBricks(classify_, volumes_)) return;
    const size_t others = std::max<size_t>(volumes_.bricks().ranges.size(), 1) - 1;
    const std::string why = classify_.emptyReason() + (others == 1 ? ", nor in the other volume"
                                                       : others > 1 ? ", nor in the other " + std::to_string(others) + " volumes"
                                                                    : "");
    if (!run.scene.value("/input/allow_empty").get<bool>()) throw InputError(why);
    run.warnings.push_back(why + "; rendered as an empty frame");
}

StageReads VolumesStage::reads() const {
    return {{"/volumes/*/path", "/volumes/*/density", "/volumes/*/level_set", "/volumes/*/material", "/volumes/*/emission", "/volumes/*/instances?",
             "/volumes/*/role", "/input/volume_files", "/input/light_links/sets", "/render/filter", "/render/motion_blur?", "/render/motion_blur/velocity",
             "/render/motion_blur/shutter", "/render/motion_blur/velocity_scale", "/render/motion_blur/fps", "/volumes/*/holdout_mesh?",
             "/holdouts", "/input/holdout_files", "/input/holdout_placements"}};
}

StageActivity VolumesStage::activity(const Scene& s) const {
    if (!rendersAsSeveral(s)) return {false, "skipped: one volume"};
    if (s.volumes.size() == 1) return {true, "places the volume over its bricks (" + std::to_string(placedVolumeCount(s)) + " placed)"};
    const size_t meshes = size_t(std::count_if(s.volumes.begin(), s.volumes.end(), [](const VolumeSpec& v) { return v.holdout_mesh.has_value(); }));
    const size_t own = s.volumes.size() - meshes;
    std::string what = own == 1 ? "" : "loads, bricks and classifies volumes 2 to " + std::to_string(own);
    if (meshes)
        what += (what.empty() ? "" : ", ") + std::string("voxelises ") + (meshes == 1 ? "the holdout mesh" : std::to_string(meshes) + " holdout meshes") +
                " into cells that shadow";
    return {true, what + " (each only when its own keys changed) and joins all into one atlas"};
}

namespace {

// Where a mesh holdout's cells are made: the world box of the scene's own volumes' bricks where
// they sit (grown by the holdout's shadow_reach), and the cells' default edge, the finest of their
// voxels.
struct CellsClip {
    glm::vec3 lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
    float voxel = std::numeric_limits<float>::max();
};

// `placements`: the render document's /input/holdout_placements/volumes, each volume's copies.
CellsClip cellsClip(const std::vector<std::pair<const BrickAtlas*, const PageTable*>>& volumes, const nlohmann::json& placements) {
    CellsClip clip;
    for (size_t v = 0; v < volumes.size(); ++v) {
        const PageTable& pages = *volumes[v].second;
        if (glm::any(glm::lessThan(pages.bricks_max, pages.bricks_min))) continue;
        const glm::vec3 lo = glm::vec3(pages.bricks_min * 8) - 0.5f, hi = glm::vec3(pages.bricks_max * 8 + 7) + 0.5f;
        for (const nlohmann::json& m : placements.at(v)) {
            const glm::mat4 to_world = matrixFromJson(m) * volumes[v].first->index_to_world;
            clip.voxel = std::min(clip.voxel, voxelEdge(to_world));
            for (int c = 0; c < 8; ++c) {
                const glm::vec3 corner(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
                const glm::vec3 w = glm::vec3(to_world * glm::vec4(corner, 1.0f));
                clip.lo = glm::min(clip.lo, w), clip.hi = glm::max(clip.hi, w);
            }
        }
    }
    return clip;
}

// How holdouts[h]'s cells are made this frame: where its mesh sits (`placement`, the render
// document's), over which world box and how finely; none when the volumes have no bricks.
struct CellsPlan {
    glm::mat4 placement{1.0f};
    float cell = 1.0f;
    glm::vec3 lo{0.0f}, hi{0.0f};
    bool none = true;
    std::string key() const { return matrixToJson(placement).dump() + jsonVec3(lo).dump() + jsonVec3(hi).dump() + nlohmann::json(jsonDecimal(cell)).dump(); }
};

CellsPlan cellsPlan(const CellsClip& clip, const Holdout& holdout, const nlohmann::json& placement) {
    CellsPlan plan;
    plan.placement = matrixFromJson(placement);
    if (clip.lo.x > clip.hi.x) return plan;
    const glm::vec3 side = clip.hi - clip.lo;
    const glm::vec3 reach(holdout.shadow_reach ? *holdout.shadow_reach : std::max({side.x, side.y, side.z}));
    plan.cell = holdout.voxel_size > 0.0f ? holdout.voxel_size : clip.voxel;
    plan.lo = clip.lo - reach, plan.hi = clip.hi + reach;
    plan.none = false;
    return plan;
}

}  // namespace

void VolumesStage::run(StageRun& run) {
    const Scene& scene = run.scene(reads().keys);
    std::vector<Kept> before = std::move(kept_);
    kept_.assign(scene.volumes.size() - 1, Kept{});
    std::optional<CellsClip> clip;   // made when the first mesh holdout's volume needs it
    for (size_t v = 1; v < scene.volumes.size(); ++v) {
        const VolumeSpec& spec = scene.volumes[v];
        const std::string at = "/volumes/" + std::to_string(v);
        nlohmann::json entry = run.scene.value(at);
        for (const char* placement_or_name : {"transform", "instances", "name", "role"}) entry.erase(placement_or_name);
        const nlohmann::json& file = run.scene.value("/input/volume_files/" + std::to_string(v));
        std::string key = entry.dump() + file.dump() + run.scene.value("/render/filter").dump();
        const nlohmann::json& mesh = spec.holdout_mesh ? run.scene.value("/input/holdout_files/" + std::to_string(*spec.holdout_mesh)) : file;
        CellsPlan cells;
        if (spec.holdout_mesh) {   // the scene's own volumes come first: all are kept_ or brick_ by now
            const nlohmann::json& placements = run.scene.value("/input/holdout_placements");
            if (!clip) {
                std::vector<std::pair<const BrickAtlas*, const PageTable*>> own{{&brick_.atlas(), &classify_.pages()}};
                for (size_t o = 1; o < v; ++o) own.emplace_back(&kept_[o - 1].atlas, &kept_[o - 1].pages);
                clip = cellsClip(own, placements.at("volumes"));
            }
            cells = cellsPlan(*clip, scene.holdouts.at(*spec.holdout_mesh), placements.at("meshes").at(*spec.holdout_mesh));
            key += cells.key() + mesh.dump();
        }
        if (scene.render.motion_blur)   // what loading and bricking take of it: the velocity and its reach
            for (const char* what : {"velocity", "shutter", "velocity_scale", "fps"})
                key += run.scene.value(std::string("/render/motion_blur/") + what).dump();
        Kept& k = kept_[v - 1];
        // Kept under its key, not its place: the volumes after a disabled one move up the list.
        const auto same = std::find_if(before.begin(), before.end(), [&](const Kept& b) { return b.key == key; });
        if (same != before.end()) {
            k = std::move(*same);
            same->key.clear();   // taken: a second volume of the same key loads its own
            run.reused.push_back("volumes: " + scene.volumes[v].name);
            continue;
        }
        const std::string path = (spec.holdout_mesh ? mesh : file).at("path").get<std::string>();
        static const TriangleMesh no_triangles;
        const LoadedVolume loaded =
            !spec.holdout_mesh ? loadVolume(path, spec, scene.render.motion_blur)
                               : voxelisedMesh(cells.none ? no_triangles : *meshes_.mesh(*spec.holdout_mesh), cells.placement, cells.cell, cells.lo, cells.hi, path);
        run.warnings.insert(run.warnings.end(), loaded.warnings.begin(), loaded.warnings.end());
        k.atlas = buildBrickAtlas(loaded, motionReachBricks(loaded, scene.render.motion_blur));
        for (const std::string& w : sanitizeReport(k.atlas, loaded)) run.warnings.push_back(w);
        k.pages = classifiedPageTable(k.atlas, spec, scene.render.filter);
        k.key = key;
    }
    std::vector<const BrickAtlas*> atlases{&brick_.atlas()};
    std::vector<const PageTable*> pages{&classify_.pages()};
    for (const Kept& k : kept_) {
        atlases.push_back(&k.atlas);
        pages.push_back(&k.pages);
    }
    joined_ = joinVolumeBricks(atlases, pages);
}

bool noVisibleBricks(const ClassifyStage& classify, const VolumesStage& volumes) {
    const std::vector<kernel::VxPageRange>& ranges = volumes.bricks().ranges;
    return classify.pages().empty() && std::all_of(ranges.begin(), ranges.end(), isEmptyRange);
}

StageReads CameraStage::reads() const { return {withPlacementKeys({"/camera", "/render/resolution", "/volumes/*/up", "/input/camera_file"})}; }

StageActivity CameraStage::activity(const Scene& s) const {
    return {true, s.camera                      ? "the scene's camera"
                  : framesSeveral(s)         ? "frames all volumes' bricks (no camera in the scene)"
                                         : "frames the density grid's active voxels (no camera in the scene)"};
}

namespace {

// The default camera of several volumes: framing the world box of all their placed bricks.
Camera frameVolumes(const SceneBricks& bricks, const Scene& scene, float frame, const LoadedVolume& first) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (size_t v = 0; v < scene.volumes.size(); ++v) {
        if (scene.volumes[v].holdout_mesh) continue;   // the CG's cells: held out, never framed
        for (const glm::mat4& placement : instancePlacements(scene.volumes[v], frame))
            growByPageRange(bricks.ranges[v], placement * bricks.index_to_world[v], lo, hi);
    }
    if (lo.x > hi.x) lo = hi = glm::vec3(0.0f);
    return frameBox(lo, hi, Camera{}.fov, float(scene.render.width) / float(scene.render.height), viewFrameOf(scene, first));
}

}  // namespace

void CameraStage::run(StageRun& run) {
    const Scene& scene = run.scene({"/camera", "/render/resolution", "/volumes/*/up", "/volumes/*/transform", "/input/camera_file"});
    if (scene.camera)
        camera_ = posedCamera(*scene.camera, run.scene.frame());
    else if (framesSeveral(scene))   // one volume frames the same with its lights linked or held out or not
        camera_ = frameVolumes(volumes_.bricks(), scene, run.scene.frame(), load_.volume());
    else
        camera_ = frameActiveVoxels(placedVolume(load_.volume(), volumePlacement(scene.volume(), run.scene.frame())), scene);
}

glm::mat3 viewFrameOf(const Scene& scene, const LoadedVolume& volume) {
    return scene.volume().up == UpAxis::Auto ? volume.up.frame : upFrame(int(scene.volume().up) - int(UpAxis::X));
}

Camera frameActiveVoxels(const LoadedVolume& volume, const Scene& scene) {
    openvdb::CoordBBox box = volume.density->evalActiveVoxelBoundingBox();
    glm::vec3 lo(0.0f), hi(1.0f);
    if (!box.empty()) voxelBoxWorldBounds(volume.index_to_world, box, lo, hi);
    return frameBox(lo, hi, Camera{}.fov, float(scene.render.width) / float(scene.render.height), viewFrameOf(scene, volume));
}

}  // namespace voxlux
