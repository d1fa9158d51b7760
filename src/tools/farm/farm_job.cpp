#include "tools/farm/farm_job.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_reader.h"
#include "io/exr_writer.h"
#include "render/write_stage.h"
#include "scene/scene_json.h"

namespace voxlux {
namespace fs = std::filesystem;

std::vector<std::string> FarmJob::taskCommand(int64_t index) const {
    std::vector<std::string> command{voxlux, "render", sceneFile(), "--frames", chunkFrames(index).text(), "--resume",
                                     "--log-json", logDir() + "/chunk_" + std::to_string(index) + ".jsonl"};
    if (cpus > 0) command.insert(command.end(), {"--threads", std::to_string(cpus)});   // the cores the scheduler gave, no more
    return command;
}

std::string chunkList(const std::vector<int64_t>& chunks) {
    FrameSet set;
    for (int64_t c : chunks) set.add(int(c));
    return set.text();
}

FarmJob createFarmJob(const Scene& scene, const std::string& dir, int64_t chunk, const std::string& voxlux,
                      const std::string& partition, int cpus) {
    if (chunk < 1) throw InputError("--chunk " + std::to_string(chunk) + ": must be at least 1 frame");
    FarmJob job;
    job.dir = fs::absolute(dir).lexically_normal().string();
    if (!job.dir.empty() && job.dir.back() == '/') job.dir.pop_back();
    if (fs::exists(job.dir + "/job.json"))
        throw InputError(job.dir + ": holds a farm job already (voxlux farm collect it, or choose another --job-dir)");
    job.frames = scene.volume().frames.value();
    job.chunk = chunk;
    job.voxlux = voxlux;
    job.partition = partition;
    job.cpus = cpus;
    fs::create_directories(job.logDir());

    Scene task_scene = scenePathsRelativeTo(scene, job.dir);
    for (std::string* out : {&task_scene.output.path, &task_scene.output.preview})
        if (!out->empty()) *out = fs::absolute(*out).lexically_normal().string();
    writeFileAtomically(job.sceneFile(), jsonText(sceneToJson(task_scene), 2) + "\n");
    saveFarmJob(job);
    return job;
}

void saveFarmJob(const FarmJob& job) {
    nlohmann::json j = {{"frames", job.frames.text()}, {"chunk", job.chunk}, {"voxlux", job.voxlux},
                        {"partition", job.partition}, {"cpus", job.cpus}, {"submissions", nlohmann::json::array()}};
    for (const auto& s : job.submissions)
        j["submissions"].push_back({{"scheduler", s.scheduler}, {"job_id", s.job_id}, {"chunks", s.chunks}});
    writeFileAtomically(job.dir + "/job.json", jsonText(j, 2) + "\n");
}

FarmJob loadFarmJob(const std::string& dir) {
    FarmJob job;
    job.dir = fs::absolute(dir).lexically_normal().string();
    if (!job.dir.empty() && job.dir.back() == '/') job.dir.pop_back();
    const std::string file = job.dir + "/job.json";
    std::ifstream in(file);
    if (!in) throw InputError(file + ": no farm job here (voxlux farm submit makes one)");
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        job.frames = FrameSet::parse(j.at("frames").get<std::string>());
        job.chunk = j.at("chunk").get<int64_t>();
        job.voxlux = j.at("voxlux").get<std::string>();
        job.partition = j.at("partition").get<std::string>();
        job.cpus = j.at("cpus").get<int>();
        for (const auto& s : j.at("submissions"))
            job.submissions.push_back({s.at("scheduler").get<std::string>(), s.at("job_id").get<std::string>(),
                                       s.at("chunks").get<std::vector<int64_t>>()});
        if (job.chunk < 1) throw std::invalid_argument("chunk must be at least 1");
    } catch (const std::exception& e) {
        throw InputError(file + ": not a voxlux farm job (" + e.what() + ")");
    }
    return job;
}

std::vector<FrameOutcome> checkFarmFrames(const FarmJob& job) {
    const Scene scene = loadSceneFile(job.sceneFile());
    const std::string hash = sceneHash(scene);
    std::vector<FrameOutcome> out;
    for (int64_t k = 0; k < job.frames.count(); ++k) {
        const int frame = job.frames.at(k);
        out.push_back({frame, k / job.chunk, checkFrame(scene, frame, hash)});
    }
    return out;
}

}  // namespace voxlux
