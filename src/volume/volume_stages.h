// The stages that turn a frame's file into what the lighting and the march read: load (the VDB
// grids), brick (the atlas of 8^3 bricks with aprons), classify (the page table of the bricks the
// material makes visible) and camera (the scene's, or one framing the active voxels).
// Cost: load and brick follow the active voxels, never the bounding box; classify is one pass
// over the bricks' value ranges; camera one bounding-box query of the density tree. Load and
// brick share their outputs with the graph's output cache (a viewer's frames within a budget).
#pragma once
#include <memory>
#include <optional>

#include "volume/brick_atlas.h"
#include "volume/page_table.h"
#include "volume/scene_bricks.h"
#include "graph/render_graph.h"
#include "volume/holdout_mesh_stage.h"
#include "volume/vdb_loader.h"

namespace voxlux {

// `keys` and those of the volumes' placement at the frame and their roles, for a stage whose
// output follows where the volumes sit and whether they march as several (rendersAsSeveral): the
// camera's framing and every stage that makes kernel inputs. The bricks do not: they stay in the
// file's index space, so a move re-reads and re-bricks nothing.
inline std::vector<std::string> withPlacementKeys(std::vector<std::string> keys) {
    keys.insert(keys.end(), {"/volumes/*/transform", "/volumes/*/instances", "/volumes/*/role", "/input/frame", "/input/transform_chan"});
    return keys;
}

class LoadStage final : public Stage {
public:
    LoadStage() = default;
    // Renders `given` (grids made in memory) instead of reading the scene's files.
    explicit LoadStage(LoadedVolume given) : given_(std::move(given)) {}
    std::string name() const override { return "load"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void stale() override { volume_.reset(); }
    SharedOutput sharedOutput() const override { return volume_; }
    size_t outputBytes() const override;
    void adoptOutput(const SharedOutput& kept) override { volume_ = kept.as<LoadedVolume>(); }
    bool given() const { return given_.has_value(); }
    const LoadedVolume& volume() const { return *volume_; }

private:
    std::optional<LoadedVolume> given_;
    std::shared_ptr<const LoadedVolume> volume_;
};

// Kniss 2002's two-dimensional transfer function (material.transfer_function_2d), when the scene
// has one: the loaded grid's voxels classified by value and gradient magnitude into an extinction
// and an albedo grid (volume/transfer_2d.h). Otherwise it does not run, and volume() is load's.
// A stage of its own so that editing the regions re-reads no file; its grids are shared with the
// output cache, as load's, so that a viewer scrubbing a sequence does not classify a frame twice.
class Transfer2dStage final : public Stage {
public:
    explicit Transfer2dStage(const LoadStage& load) : load_(input(load)) {}
    std::string name() const override { return "transfer_2d"; }
    StageReads reads() const override { return {{"/volumes/*/material/transfer_function_2d"}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void release() override { volume_.reset(); }
    void stale() override { volume_.reset(); }
    SharedOutput sharedOutput() const override { return volume_; }
    size_t outputBytes() const override;
    void adoptOutput(const SharedOutput& kept) override { volume_ = kept.as<LoadedVolume>(); }
    const LoadedVolume& volume() const { return volume_ ? *volume_ : load_.volume(); }

private:
    const LoadStage& load_;
    std::shared_ptr<const LoadedVolume> volume_;
};

class BrickStage final : public Stage {
public:
    explicit BrickStage(const Transfer2dStage& load) : load_(input(load)) {}
    std::string name() const override { return "brick"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void stale() override { atlas_.reset(); }
    SharedOutput sharedOutput() const override { return atlas_; }
    size_t outputBytes() const override { return atlas_ ? atlas_->bytes() : 0; }
    void adoptOutput(const SharedOutput& kept) override { atlas_ = kept.as<BrickAtlas>(); }
    const BrickAtlas& atlas() const { return *atlas_; }

private:
    const Transfer2dStage& load_;
    std::shared_ptr<const BrickAtlas> atlas_;
};

class ClassifyStage final : public Stage {
public:
    ClassifyStage(const Transfer2dStage& load, const BrickStage& brick) : load_(input(load)), brick_(input(brick)) {}
    std::string name() const override { return "classify"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    const PageTable& pages() const { return pages_; }
    const std::string& emptyReason() const { return empty_reason_; }   // why nothing is visible, or ""

private:
    const Transfer2dStage& load_;
    const BrickStage& brick_;
    PageTable pages_;
    std::string empty_reason_;
};

class VolumesStage;

// Refuses a frame with nothing visible in any volume (InputError), unless the render document's
// /input/allow_empty says a sequence may have such frames; then it warns. A stage of its own, so
// that allowing empty frames re-runs nothing but the stages after it.
class EmptyFrameStage final : public Stage {
public:
    EmptyFrameStage(const ClassifyStage& classify, const VolumesStage& volumes) : classify_(input(classify)), volumes_(input(volumes)) {}
    std::string name() const override { return "empty_check"; }
    StageReads reads() const override { return {{"/input/allow_empty"}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;

private:
    const ClassifyStage& classify_;
    const VolumesStage& volumes_;
};

// The volumes of a scene of several after the first (whose stages are load, brick and classify):
// each loaded, bricked and classified as those do, and kept while its own keys (its entry but the
// transform, its file, the filter, and the motion blur's velocity keys) stay the same, wherever it
// moves in the list, so an edit of one volume, or one after the first disabled or enabled again,
// reloads no other; then all joined into one atlas (volume/scene_bricks.h). It does not run for
// one volume.
// Cost: the changed volumes' load, brick and classify, and one copy of every volume's bricks.
//
// A mesh holdout's volume (VolumeSpec::holdout_mesh, after the scene's own) is made from its mesh
// (volume/mesh_voxels.h) over the world box of the scene's own volumes where they sit, kept while
// its mesh, its placement, that box and the cells' size stay the same.
class VolumesStage final : public Stage {
public:
    VolumesStage(const BrickStage& brick, const ClassifyStage& classify, const HoldoutMeshStage& meshes)
        : brick_(input(brick)), classify_(input(classify)), meshes_(input(meshes)) {}
    std::string name() const override { return "volumes"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void release() override { joined_ = SceneBricks{}; }
    const SceneBricks& bricks() const { return joined_; }

private:
    struct Kept {
        std::string key;
        BrickAtlas atlas;
        PageTable pages;
    };
    const BrickStage& brick_;
    const ClassifyStage& classify_;
    const HoldoutMeshStage& meshes_;
    std::vector<Kept> kept_;   // volumes 1, 2, ...
    SceneBricks joined_;
};

// Whether no volume of the scene has a brick to render: the first volume's classified pages are
// empty, and so is every other volume's range. The light grid's stages idle then.
bool noVisibleBricks(const ClassifyStage& classify, const VolumesStage& volumes);

class CameraStage final : public Stage {
public:
    CameraStage(const Transfer2dStage& load, const VolumesStage& volumes) : load_(input(load)), volumes_(input(volumes)) {}
    std::string name() const override { return "camera"; }
    StageReads reads() const override;
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    const Camera& camera() const { return camera_; }

private:
    const Transfer2dStage& load_;
    const VolumesStage& volumes_;
    Camera camera_;
};

// The default view's frame (right, up, back; volume/up_axis.h): the scene's volume.up, else what
// the file says.
glm::mat3 viewFrameOf(const Scene& scene, const LoadedVolume& volume);

// Camera framing the active voxels of the density grid: what a scene without a camera renders
// and what `voxlux scene` writes out.
Camera frameActiveVoxels(const LoadedVolume& volume, const Scene& scene);

}  // namespace voxlux
