#include "tools/farm/slurm_scheduler.h"

#include <filesystem>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/progress.h"
#include "io/exr_writer.h"
#include "tools/farm/process.h"

namespace voxlux {
namespace {

// The batch script: one case per chunk, so the array's task id alone picks the frames.
std::string batchScript(const FarmJob& job) {
    std::ostringstream s;
    s << "#!/bin/sh\n"
      << "# Written by voxlux farm submit: task k of the array renders chunk k of " << job.dir << "\n"
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

// Slurm's MaxArraySize (task ids run below it), from the controller; its default where it cannot say.
int64_t maxArraySize() {
    const ProcessResult r = runProcess({"scontrol", "show", "config"});
    std::istringstream lines(r.output);
    for (std::string line; std::getline(lines, line);) {
        const size_t eq = line.find('=');
        if (line.rfind("MaxArraySize", 0) == 0 && eq != std::string::npos) {
            try {
                return std::stoll(line.substr(eq + 1));
            } catch (const std::exception&) {
                break;
            }
        }
    }
    return 1001;
}

// The states after which a task runs no more (Slurm's job state codes); any other may still run.
bool ended(const std::string& state) {
    static const std::set<std::string> final{"COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "PREEMPTED",
                                             "BOOT_FAIL", "DEADLINE", "OUT_OF_MEMORY", "REVOKED"};
    return final.count(state) > 0;
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
        out[std::stoll(task)] = {state, !ended(state)};
    }
}

}  // namespace

std::string SlurmScheduler::submit(const FarmJob& job, const std::vector<int64_t>& chunks, bool dry_run) {
    const int64_t limit = maxArraySize();
    if (job.chunkCount() > limit)
        throw InputError("--chunk " + std::to_string(job.chunk) + ": " + std::to_string(job.chunkCount()) +
                         " chunks, past Slurm's MaxArraySize of " + std::to_string(limit) + " tasks; use --chunk " +
                         std::to_string((job.frames.count() + limit - 1) / limit) + " or more");
    const std::string script = job.dir + "/slurm.sh";
    writeFileAtomically(script, batchScript(job));
    // On the command line, not as #SBATCH lines: a path with spaces or % stays one argument.
    std::vector<std::string> command = {"sbatch", "--parsable", "--array=" + chunkList(chunks),
                                        "--job-name=voxlux-" + std::filesystem::path(job.dir).filename().string(),
                                        "--output=" + job.logDir() + "/chunk_%a.out", "--open-mode=append"};
    if (job.cpus > 0) command.push_back("--cpus-per-task=" + std::to_string(job.cpus));
    if (!job.partition.empty()) command.push_back("--partition=" + job.partition);
    command.push_back(script);
    if (dry_run) return "dry run: " + shellCommand(command);
    const ProcessResult r = runProcess(command);
    // --parsable prints "12" or "12;cluster" last; warnings and site messages go before it or to stderr.
    const std::string last = lastLine(r.output);
    const std::string id = last.substr(0, last.find(';'));
    if (r.exit_code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
        const std::string message = lastLine(r.error).empty() ? lastLine(r.output) : lastLine(r.error);
        throw InputError("sbatch: " + (message.empty() ? "exit " + std::to_string(r.exit_code) : message));
    }
    return id;
}

std::map<int64_t, TaskState> SlurmScheduler::tasks(const FarmSubmission& submission) {
    std::map<int64_t, TaskState> states;
    const ProcessResult accounted = runProcess({"sacct", "--noheader", "--parsable2", "--allocations", "--jobs", submission.job_id,
                                                "--format=JobID,State"});
    if (accounted.exit_code == 0) readStates(accounted.output, submission.job_id, '|', states);
    // squeue knows the tasks still queued (sacct may lag) and, without accounting, those that ended
    // within MinJobAge. A job it no longer knows is "Invalid job id"; any other failure is not an
    // answer, and must not read as "every task ended".
    const ProcessResult queued = runProcess({"squeue", "--noheader", "--array", "--states=all", "--jobs", submission.job_id,
                                             "--format=%i %T"});
    throwIfInterrupted();   // Ctrl-C reached squeue too
    if (queued.exit_code == 0) readStates(queued.output, submission.job_id, ' ', states);
    else if (queued.error.find("Invalid job id") == std::string::npos)
        throw InputError("squeue: " + (lastLine(queued.error).empty() ? "exit " + std::to_string(queued.exit_code) : lastLine(queued.error)));
    return states;
}

std::unique_ptr<Scheduler> makeScheduler(const std::string& name) {
    if (name == "slurm") return std::make_unique<SlurmScheduler>();
    throw InputError("--scheduler " + name + ": not a scheduler voxlux knows (slurm)");
}

}  // namespace voxlux
