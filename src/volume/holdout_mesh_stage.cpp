#include "volume/holdout_mesh_stage.h"

#include <algorithm>

#include "scene/scene_json.h"

namespace voxlux {

StageActivity HoldoutMeshStage::activity(const Scene& s) const {
    const size_t n = size_t(std::count_if(s.holdouts.begin(), s.holdouts.end(), [](const Holdout& h) { return !h.mesh.empty(); }));
    if (n == 0) return {false, "skipped: no mesh holdouts"};
    return {true, "reads " + std::to_string(n) + (n == 1 ? " mesh" : " meshes") + " (each only when its file changed)"};
}

void HoldoutMeshStage::run(StageRun& run) {
    const Scene& scene = run.scene({"/holdouts"});
    std::vector<std::shared_ptr<const TriangleMesh>> meshes(scene.holdouts.size());
    std::vector<std::string> files(scene.holdouts.size());
    for (size_t h = 0; h < scene.holdouts.size(); ++h) {
        if (scene.holdouts[h].mesh.empty()) continue;
        const nlohmann::json& file = run.scene.value("/input/holdout_files/" + std::to_string(h));
        files[h] = file.dump();
        const auto same = std::find(files_.begin(), files_.end(), files[h]);
        if (same != files_.end()) {
            meshes[h] = meshes_[size_t(same - files_.begin())];
            run.reused.push_back("holdout_meshes: " + file.at("path").get<std::string>());
            continue;
        }
        meshes[h] = std::make_shared<const TriangleMesh>(readMeshFile(file.at("path").get<std::string>()));
    }
    meshes_ = std::move(meshes);
    files_ = std::move(files);
}

glm::mat4 holdoutPlacement(const Holdout& holdout, double frame) {
    return holdout.transform ? volumeTransformMatrix(*holdout.transform, frame) : glm::mat4(1.0f);
}

nlohmann::json holdoutPlacements(const Scene& scene, double frame) {
    if (std::all_of(scene.holdouts.begin(), scene.holdouts.end(), [](const Holdout& h) { return h.mesh.empty(); })) return nullptr;
    nlohmann::json out = {{"volumes", nlohmann::json::array()}, {"meshes", nlohmann::json::array()}};
    for (const VolumeSpec& v : scene.volumes) {
        if (v.holdout_mesh || !v.enabled) continue;
        nlohmann::json& copies = out["volumes"].emplace_back(nlohmann::json::array());
        for (const glm::mat4& m : instancePlacements(v, frame)) copies.push_back(matrixToJson(m));
    }
    for (const Holdout& h : scene.holdouts) out["meshes"].push_back(matrixToJson(holdoutPlacement(h, frame)));
    return out;
}

}  // namespace voxlux
