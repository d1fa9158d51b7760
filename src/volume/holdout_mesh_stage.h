// The meshes of the scene's mesh holdouts (holdouts[i].mesh) for the frame, each read once
// (scene/mesh_file.h) and kept while its file stays the same, for the two stages that use them:
// volumes voxelises each into the cells that shadow (volume/mesh_voxels.h), holdouts casts the
// camera's rays into them (render/holdout_stage.h).
// Cost: assimp's import of each new or changed file; the triangles, 24 bytes each with their points.
#pragma once
#include <memory>
#include <vector>

#include "graph/render_graph.h"
#include "scene/mesh_file.h"

namespace voxlux {

class HoldoutMeshStage final : public Stage {
public:
    std::string name() const override { return "holdout_meshes"; }
    StageReads reads() const override { return {{"/holdouts", "/input/holdout_files"}}; }
    StageActivity activity(const Scene& scene) const override;
    void run(StageRun& run) override;
    void release() override { meshes_.clear(), files_.clear(); }
    // holdouts[h]'s mesh in its file's space; null for a depth holdout.
    const TriangleMesh* mesh(size_t h) const { return h < meshes_.size() ? meshes_[h].get() : nullptr; }

private:
    std::vector<std::shared_ptr<const TriangleMesh>> meshes_;
    std::vector<std::string> files_;   // each one's file identity when read
};

// The world placement of holdouts[h]'s mesh at `frame` (its transform, or the identity).
glm::mat4 holdoutPlacement(const Holdout& holdout, double frame);

// The render document's /input/holdout_placements of `scene` at `frame`, where the meshes'
// shadowing cells are made: {"volumes": each enabled volume's copies' placements, "meshes": each
// holdout's}, as matrices; null without mesh holdouts, so that a volume's move re-makes nothing
// then (VolumesStage reads it).
nlohmann::json holdoutPlacements(const Scene& scene, double frame);

}  // namespace voxlux
