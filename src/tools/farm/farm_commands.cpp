#include "tools/farm/farm_commands.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <ostream>
#include <thread>

#include "core/error.h"
#include "core/progress.h"
#include "render/renderer.h"
#include "tools/farm/farm_job.h"
#include "tools/farm/scheduler.h"
#include "tools/sequence_render.h"

namespace voxlux {
namespace fs = std::filesystem;
namespace {

// "fire/fluid_data_####.vdb" -> "fluid_data.farm"
std::string defaultJobDir(const std::string& input) {
    std::string stem = fs::path(input).stem().string();
    stem.erase(std::remove(stem.begin(), stem.end(), '#'), stem.end());
    while (!stem.empty() && (stem.back() == '_' || stem.back() == '.' || stem.back() == '-')) stem.pop_back();
    return (stem.empty() ? "voxlux" : stem) + ".farm";
}

std::string thisBinary() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw InputError("/proc/self/exe: cannot find the voxlux binary the tasks should run (" + ec.message() + ")");
    return self.string();
}

// Each chunk's state in the submission that ran it last.
std::map<int64_t, TaskState> chunkStates(const FarmJob& job) {
    std::map<int64_t, TaskState> states;
    for (const FarmSubmission& s : job.submissions) {
        const std::map<int64_t, TaskState> tasks = makeScheduler(s.scheduler)->tasks(s);
        for (int64_t c : s.chunks) {
            const auto it = tasks.find(c);
            if (it != tasks.end()) states[c] = it->second;
            else states.erase(c);   // this submission ran it, and the scheduler forgot it
        }
    }
    return states;
}

void waitForJob(const FarmJob& job) {
    ProgressTask progress("farm job", job.chunkCount(), "chunks");
    int64_t shown = 0;
    for (;;) {
        int64_t active = 0;
        for (const auto& [chunk, state] : chunkStates(job)) active += state.active;
        const int64_t ended = job.chunkCount() - active;
        if (ended > shown) progress.advance(ended - shown), shown = ended;
        if (!active) return;
        std::this_thread::sleep_for(std::chrono::seconds(1));
        throwIfInterrupted();   // Ctrl-C stops the wait, not the job
    }
}

}  // namespace

int farmSubmit(const Scene& scene, const std::string& input, const FarmSubmitOptions& options, std::ostream& out) {
    const std::optional<FrameSet> frames = sequenceFrames(scene);
    if (!frames) throw InputError(input + ": renders one file; a farm job needs a #### sequence and its frames");
    if (const auto problem = outputPathProblem(scene)) throw InputError(*problem);
    const std::unique_ptr<Scheduler> scheduler = makeScheduler(options.scheduler);
    FarmJob job = createFarmJob(scene, options.job_dir.empty() ? defaultJobDir(input) : options.job_dir, options.chunk,
                                thisBinary(), options.partition, options.cpus);
    std::vector<int64_t> chunks;
    for (int64_t k = 0; k < job.chunkCount(); ++k) chunks.push_back(k);
    std::string id;
    try {
        id = scheduler->submit(job, chunks, options.dry_run);
    } catch (const InputError&) {
        fs::remove(job.dir + "/job.json");   // nothing was submitted: the folder may be submitted again
        throw;
    }
    const std::string what = std::to_string(chunks.size()) + " chunks of up to " + std::to_string(job.chunk) + " frames (frames " +
                             job.frames.text() + ")";
    if (options.dry_run) {
        out << "wrote " << job.dir << " for " << what << "; " << id << "\n";
        fs::remove(job.dir + "/job.json");   // nothing was submitted: the folder may be submitted for real
        return 0;
    }
    job.submissions.push_back({scheduler->name(), id, chunks});
    saveFarmJob(job);
    out << "submitted " << what << " as " << scheduler->name() << " job " << id << "; job folder " << job.dir << "\n";
    if (!options.wait) return 0;
    waitForJob(job);
    return farmCollect(job.dir, {}, out);
}

int farmStatus(const std::string& job_dir, std::ostream& out) {
    const FarmJob job = loadFarmJob(job_dir);
    out << job.dir << ": frames " << job.frames.text() << " in " << job.chunkCount() << " chunks of up to " << job.chunk << "\n";
    for (const FarmSubmission& s : job.submissions)
        out << "  " << s.scheduler << " job " << s.job_id << ": chunks " << chunkList(s.chunks) << "\n";
    const std::map<int64_t, TaskState> states = chunkStates(job);
    std::map<std::string, int64_t> counts;
    for (int64_t k = 0; k < job.chunkCount(); ++k) {
        const auto it = states.find(k);
        const std::string state = it == states.end() ? "GONE" : it->second.state;
        ++counts[state];
        if (state != "COMPLETED") out << "  chunk " << k << " (frames " << job.chunkFrames(k).text() << "): " << state << "\n";
    }
    out << "tasks:";
    for (const auto& [state, n] : counts) out << " " << n << " " << state;
    out << (counts.count("GONE") ? "  (GONE: no longer known to the scheduler; voxlux farm collect checks their frames)" : "") << "\n";
    return 0;
}

int farmCollect(const std::string& job_dir, const FarmCollectOptions& options, std::ostream& out) {
    FarmJob job = loadFarmJob(job_dir);
    if (options.wait) waitForJob(job);
    const std::map<int64_t, TaskState> states = chunkStates(job);
    std::vector<FrameOutcome> outcomes = checkFarmFrames(job);
    FrameSet bad_frames;
    std::vector<int64_t> resubmit, running;
    for (const FrameOutcome& f : outcomes) {
        if (f.check.state == FrameCheck::State::Done) continue;
        bad_frames.add(f.frame);
        const auto state = states.find(f.chunk);
        const bool active = state != states.end() && state->second.active;
        out << "frame " << f.frame << " (chunk " << f.chunk << "): " << frameStateName(f.check.state) << ": " << f.check.reason
            << (active ? " (its task is " + state->second.state + ")" : "") << "\n";
        std::vector<int64_t>& list = active ? running : resubmit;
        if (list.empty() || list.back() != f.chunk) list.push_back(f.chunk);
    }
    const int64_t done = int64_t(outcomes.size()) - bad_frames.count();
    out << "collect: " << done << " of " << outcomes.size() << " frames done";
    if (bad_frames.count()) out << "; not done: frames " << bad_frames.text();
    out << "\n";
    if (!running.empty()) out << "chunks " << chunkList(running) << " are still queued or running\n";
    if (resubmit.empty() || !options.resubmit) {
        if (!resubmit.empty()) out << "chunks " << chunkList(resubmit) << " lack frames: voxlux farm collect " << job.dir << " --resubmit\n";
        return bad_frames.count() ? kFramesFailed : 0;
    }
    const std::string scheduler = job.submissions.empty() ? "slurm" : job.submissions.back().scheduler;
    const std::string id = makeScheduler(scheduler)->submit(job, resubmit, false);
    job.submissions.push_back({scheduler, id, resubmit});
    saveFarmJob(job);
    out << "resubmitted chunks " << chunkList(resubmit) << " as " << scheduler << " job " << id << "\n";
    if (!options.wait) return kFramesFailed;
    return farmCollect(job.dir, {false, true}, out);
}

}  // namespace voxlux
