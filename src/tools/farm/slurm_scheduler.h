// Slurm (sbatch, squeue, sacct, scontrol): a job's chunks go in as one job array, task k running
// chunk k through a batch script written into the job folder (slurm.sh), which maps
// SLURM_ARRAY_TASK_ID to the chunk's frames. State comes from `squeue --array` while Slurm keeps
// the job (MinJobAge, 300 s by default, after it ends), and from `sacct` where accounting runs.
// Slurm's MaxArraySize (1001 by default, asked of scontrol) bounds the chunk indices, so a job
// has fewer chunks than that: submit refuses more, naming the --chunk that fits.
#pragma once
#include "tools/farm/scheduler.h"

namespace voxlux {

class SlurmScheduler final : public Scheduler {
public:
    std::string name() const override { return "slurm"; }
    std::string submit(const FarmJob& job, const std::vector<int64_t>& chunks, bool dry_run) override;
    std::map<int64_t, TaskState> tasks(const FarmSubmission& submission) override;
};

}  // namespace voxlux
