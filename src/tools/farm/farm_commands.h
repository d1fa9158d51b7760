// `voxlux farm submit | status | collect` (docs/farm.md): a sequence split into chunks of frames,
// run as one scheduler job whose tasks resume, watched, and checked frame by frame, with the
// chunks that lack frames submitted again.
#pragma once
#include <iosfwd>
#include <string>

#include "scene/scene.h"

namespace voxlux {

struct FarmSubmitOptions {
    std::string job_dir;         // "" = <input's name>.farm in the working folder
    int64_t chunk = 1;           // frames per task
    std::string scheduler = "slurm";
    std::string partition;
    int cpus = 0;                // cores a task asks for; 0 = the scheduler's default
    bool dry_run = false;        // write the job folder and script, print the submit command, submit nothing
    bool wait = false;           // wait for the job to end, then check its frames as collect does
};

struct FarmCollectOptions {
    bool resubmit = false;       // submit again the chunks with frames missing or corrupt
    bool wait = false;           // wait for queued and running tasks first (and for a resubmission)
};

// `scene` is the resolved scene of `input` (camera fixed, frames set). Returns the exit code.
int farmSubmit(const Scene& scene, const std::string& input, const FarmSubmitOptions& options, std::ostream& out);
int farmStatus(const std::string& job_dir, std::ostream& out);
// 0 when every frame is done, else kFramesFailed.
int farmCollect(const std::string& job_dir, const FarmCollectOptions& options, std::ostream& out);

}  // namespace voxlux
