// A farm job's folder, which every command of `voxlux farm` works from:
//   scene.json    the scene as each task renders it: the camera fixed (a chunk must not frame
//                 itself on its own frames), input paths relative to the folder, outputs absolute;
//   job.json      the frames, the chunk size, the binary the tasks run, and each submission's
//                 scheduler and job id;
//   logs/         each chunk's scheduler output and its --log-json lines.
// A chunk is `chunk` consecutive frames of the frame set; chunk k renders with
//   voxlux render scene.json --frames <chunk k> --resume --log-json logs/chunk_<k>.jsonl
// so a task that runs again (resubmitted, or requeued by the scheduler) skips what is done.
#pragma once
#include <string>
#include <vector>

#include "core/frame_set.h"
#include "scene/scene.h"
#include "tools/frame_check.h"

namespace voxlux {

struct FarmSubmission {
    std::string scheduler;           // "slurm"
    std::string job_id;              // the scheduler's
    std::vector<int64_t> chunks;     // the chunks it runs
};

struct FarmJob {
    std::string dir;                 // absolute
    FrameSet frames;
    int64_t chunk = 1;               // frames per chunk
    std::string voxlux;              // the binary the tasks run, absolute
    std::string partition;           // the scheduler's queue; "" = its default
    int cpus = 0;                    // cores a task asks for; 0 = the scheduler's default
    std::vector<FarmSubmission> submissions;   // oldest first

    std::string sceneFile() const { return dir + "/scene.json"; }
    std::string logDir() const { return dir + "/logs"; }
    int64_t chunkCount() const { return (frames.count() + chunk - 1) / chunk; }
    FrameSet chunkFrames(int64_t index) const { return frames.slice(index * chunk, chunk); }
    // The command chunk `index` runs.
    std::vector<std::string> taskCommand(int64_t index) const;
};

// Chunk indices, increasing, as a frame spec writes them ("0-2,5"): Slurm's --array reads the same.
std::string chunkList(const std::vector<int64_t>& chunks);

// Makes the job folder for `scene` (a sequence with a camera) and writes scene.json and job.json.
// Throws InputError when the folder holds another job, or the chunk size is below 1.
FarmJob createFarmJob(const Scene& scene, const std::string& dir, int64_t chunk, const std::string& voxlux,
                      const std::string& partition, int cpus);
// Throws InputError "<dir>/job.json: ..." when the folder holds no job.
FarmJob loadFarmJob(const std::string& dir);
void saveFarmJob(const FarmJob& job);

// Every frame of the job checked (checkFrame) against the job's scene, in frame order.
struct FrameOutcome {
    int frame = 0;
    int64_t chunk = 0;
    FrameCheck check;
};
std::vector<FrameOutcome> checkFarmFrames(const FarmJob& job);

}  // namespace voxlux
