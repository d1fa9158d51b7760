#include "tools/farm/slurm_scheduler.h"

#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "core/frame_set.h"
#include "io/exr_writer.h"
#include "tools/farm/process.h"

namespace voxlux {
namespace {

// The batch script: one case per chunk, so the array's task id alone picks the frames.
std::string batchScript(const FarmJob& job) {
    std::ostringstream s;
    s << "#!/bin/sh\n"
      << "# Written by voxlux farm submit: task k of the array renders chunk k of " << job.dir << "\n"
      << "#SBATCH --job-name=voxlux-" << std::filesystem::path(job.dir).filename().string() << "\n"
      << "#SBATCH --output=" << job.logDir() << "/chunk_%a.out\n"
      << "case \"$SLURM_ARRAY_TASK_ID\" in\n";
    for (int64_t k = 0; k < job.chunkCount(); ++k) {
        std::vector<std::string> command = job.taskCommand(k);
        command.insert(command.begin(), "exec");
        s << "  " << k << ") " << shellCommand(command) << " ;;\n";
    }
    s << "  *) echo \"voxlux: error: no chunk $SLURM_ARRAY_TASK_ID in " << job.dir << "\" >&2; exit 2 ;;\n"
      << "esac\n";
    return s.str();
}

// Chunk indices as Slurm's --array list: "0-2,5".
std::string arrayList(const std::vector<int64_t>& chunks) {
    FrameSet set;
    for (int64_t c : chunks) set.add(int(c));
    return set.text();
}

// "12_3 RUNNING" lines of `squeue --array`, or "12_3|FAILED" of sacct, into chunk states.
void readStates(const std::string& text, const std::string& job_id, char separator, std::map<int64_t, TaskState>& out) {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        const size_t sep = line.find(separator), underscore = line.find('_');
        if (sep == std::string::npos || underscore == std::string::npos || line.substr(0, underscore) != job_id) continue;
        const std::string task = line.substr(underscore + 1, sep - underscore - 1);
        if (task.empty() || task.find_first_not_of("0123456789") != std::string::npos) continue;   // "12_[3-5]", a step "12_3.batch"
        std::string state = line.substr(sep + 1);
        state = state.substr(0, state.find_first_of(" \t|"));
        const bool active = state == "PENDING" || state == "RUNNING" || state == "CONFIGURING" || state == "COMPLETING" ||
                            state == "REQUEUED" || state == "RESIZING" || state == "SUSPENDED";
        out[std::stoll(task)] = {state, active};
    }
}

}  // namespace

std::string SlurmScheduler::submit(const FarmJob& job, const std::vector<int64_t>& chunks, bool dry_run) {
    const std::string script = job.dir + "/slurm.sh";
    writeFileAtomically(script, batchScript(job));
    std::vector<std::string> command = {"sbatch", "--parsable", "--array=" + arrayList(chunks)};
    if (!job.partition.empty()) command.push_back("--partition=" + job.partition);
    command.push_back(script);
    if (dry_run) return "dry run: " + shellCommand(command);
    const ProcessResult r = runProcess(command);
    std::string id = r.output.substr(0, r.output.find_first_of(";\n"));   // "12" or "12;cluster"
    if (r.exit_code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
        std::string message = r.output;
        while (!message.empty() && message.back() == '\n') message.pop_back();
        throw InputError("sbatch: " + (message.empty() ? "exit " + std::to_string(r.exit_code) : message.substr(message.rfind('\n') + 1)));
    }
    return id;
}

std::map<int64_t, TaskState> SlurmScheduler::tasks(const FarmJob&, const FarmSubmission& submission) {
    std::map<int64_t, TaskState> states;
    const ProcessResult accounted = runProcess({"sacct", "--noheader", "--parsable2", "--allocations", "--jobs", submission.job_id,
                                                "--format=JobID,State"});
    if (accounted.exit_code == 0) readStates(accounted.output, submission.job_id, '|', states);
    // squeue knows the tasks still queued (sacct may lag) and, without accounting, those that ended.
    const ProcessResult queued = runProcess({"squeue", "--noheader", "--array", "--states=all", "--jobs", submission.job_id,
                                             "--format=%i %T"});
    if (queued.exit_code == 0) readStates(queued.output, submission.job_id, ' ', states);
    if (queued.exit_code == 127) throw InputError("squeue: " + queued.output);
    return states;
}

std::unique_ptr<Scheduler> makeScheduler(const std::string& name) {
    if (name == "slurm") return std::make_unique<SlurmScheduler>();
    throw InputError("--scheduler " + name + ": not a scheduler voxlux knows (slurm)");
}

}  // namespace voxlux
