// What `voxlux farm` needs of a render farm's scheduler: submit a job's chunks as one job (an
// array of tasks), and tell each task's state. Slurm implements it (slurm_scheduler.h); Deadline,
// OpenCue or Tractor would implement the same two calls with their own submitters and queries
// (docs/farm.md, "Another scheduler"). Everything else (the job folder, the chunks, resuming,
// checking frames) is the scheduler's no business.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "tools/farm/farm_job.h"

namespace voxlux {

struct TaskState {
    std::string state;     // the scheduler's own word: PENDING, RUNNING, COMPLETED, FAILED, CANCELLED, ...
    bool active = false;   // queued or running: its frames may still come
};

class Scheduler {
public:
    virtual ~Scheduler() = default;
    virtual std::string name() const = 0;
    // Submits `chunks` of `job` as one job and returns its id. With `dry_run`, writes what it would
    // submit and returns the command that would submit it instead, prefixed "dry run: ".
    // Throws InputError naming the scheduler's tool and its message when submission fails.
    virtual std::string submit(const FarmJob& job, const std::vector<int64_t>& chunks, bool dry_run) = 0;
    // The state of each task of `submission` the scheduler still knows, by chunk index; a chunk
    // missing from the map has left the scheduler's memory (its frames tell how it went). Throws
    // InputError when the scheduler cannot be asked: no answer is never read as "ended".
    virtual std::map<int64_t, TaskState> tasks(const FarmSubmission& submission) = 0;
};

// "slurm"; throws InputError naming the schedulers there are for any other name.
std::unique_ptr<Scheduler> makeScheduler(const std::string& name);

}  // namespace voxlux
