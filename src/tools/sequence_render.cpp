#include "tools/sequence_render.h"

#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <ostream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/frame_pattern.h"
#include "core/json_reader.h"
#include "core/peak_memory.h"
#include "core/progress.h"
#include "io/exr_writer.h"
#include "render/renderer.h"
#include "render/write_stage.h"
#include "tools/frame_check.h"

namespace voxlux {
namespace {

std::string hostName() {
    char name[256] = {};
    gethostname(name, sizeof name - 1);
    return name;
}

std::string utcNow() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text;
}

// --log-json: JSON lines appended and flushed one by one, so a killed task's log is whole up to
// its last frame.
class FrameLog {
public:
    explicit FrameLog(const std::optional<std::string>& path) {
        if (!path) return;
        makeOutputFolder(*path);
        file_.open(*path, std::ios::app);
        if (!file_) {
            const int cause = errno;
            if (const auto problem = outputProblem(*path)) throw InputError(*problem);   // the folder's, as any output's
            throw InputError(*path + ": cannot open the log for appending (" + std::strerror(cause) + ")");
        }
        path_ = *path;
    }
    void write(const nlohmann::json& line) {
        if (!file_.is_open()) return;
        file_ << jsonText(line) << "\n" << std::flush;
        if (!file_) throw InputError(path_ + ": cannot write the log");
    }

private:
    std::ofstream file_;
    std::string path_;
};

}  // namespace

double sequenceSecondsLeft(const std::vector<double>& frame_seconds, int64_t frames_left) {
    const size_t n = frame_seconds.size();
    if (n == 0 || frames_left <= 0) return 0.0;
    if (n < 3) return frame_seconds.back() * double(frames_left);
    double mean_k = 0.0, mean_t = 0.0;
    for (size_t k = 0; k < n; ++k) mean_k += double(k) / double(n), mean_t += frame_seconds[k] / double(n);
    double cov = 0.0, var = 0.0;
    for (size_t k = 0; k < n; ++k) cov += (double(k) - mean_k) * (frame_seconds[k] - mean_t), var += (double(k) - mean_k) * (double(k) - mean_k);
    const double slope = cov / var;
    // The frames left are n .. n + left - 1 on the line: their sum is left x the line at their middle.
    const double middle = double(n) + 0.5 * double(frames_left - 1);
    return std::max(0.0, double(frames_left) * (mean_t + slope * (middle - mean_k)));
}

std::optional<FrameSet> sequenceFrames(const Scene& s) {
    if (!hasFramePattern(s.volume().path)) return std::nullopt;
    if (!s.volume().frames)
        throw InputError(s.volume().path + ": path has a #### frame pattern; set volume.frames or pass --frames");
    const bool several = s.volume().frames->count() > 1;
    if (several && !s.output.path.empty() && !hasFramePattern(s.output.path))
        throw InputError(s.output.path + ": several frames need a #### pattern in the output path");
    if (several && !s.output.preview.empty() && !hasFramePattern(s.output.preview))
        throw InputError(s.output.preview + ": several frames need a #### pattern in the preview path");
    return s.volume().frames;
}

int renderSequence(const Scene& scene, const SequenceOptions& options, std::ostream& out, std::ostream& err) {
    const std::optional<FrameSet> requested = sequenceFrames(scene);
    if (const auto problem = outputPathProblem(scene)) throw InputError(*problem);
    // Frames whose file is not on disk fail without being tried, named in one line (a range typed
    // too long, a cache not written yet), and the others render: from one listing of the folder,
    // so "1-2000000000" costs nothing per frame.
    std::optional<FrameSet> frames = requested;
    FrameSet missing;
    if (requested) {
        FrameSet disk;
        try {
            disk = framesOnDisk(scene.volume().path, *requested);
        } catch (const std::invalid_argument& e) {
            throw InputError(scene.volume().path + ": " + e.what());
        }
        frames = requested->among(disk);
        missing = requested->notAmong(disk);
        if (frames->count() == 0)
            throw InputError(scene.volume().path + ": no file of frames " + requested->text() + " exists" +
                             (disk.count() ? " (on disk: frames " + disk.text() + ")" : ""));
    }
    // Before any frame, every output's folder is made and takes a file: a folder that cannot is
    // one line now, not an error after the last frame rendered.
    for (const std::string& path : frameOutputPaths(scene, frames ? std::optional<int>(frames->first()) : std::nullopt))
        checkWritable(path);
    if (options.stats) checkWritable(*options.stats);
    FrameLog log(options.log_json);
    const std::string hash = sceneHash(scene), host = hostName();
    if (missing.count()) {
        const std::string message = "frames " + missing.text() + " of " + requested->text() + " are not on disk (" +
                                    expandFramePattern(scene.volume().path, missing.first()) + ": no such file)";
        err << "voxlux: error: " << message << (options.fail_fast ? "" : "; the others render") << "\n";
        log.write({{"frames", missing.text()}, {"status", "missing"}, {"error", message}, {"host", host}, {"pid", getpid()}, {"time", utcNow()}});
        if (options.fail_fast) {
            err << "voxlux: error: " << missing.count() << " of " << requested->count() << " frames failed: " << missing.text()
                << " (stopped there, --fail-fast; " << frames->count() << " not rendered)\n";
            return kFramesFailed;
        }
    }

    Renderer renderer(scene);
    const int64_t count = frames ? frames->count() : 1;
    const auto progress = frames ? std::make_unique<ProgressTask>("sequence", count, "frames") : nullptr;
    nlohmann::json stats = {{"backend", renderer.backendName()}, {"frames", nlohmann::json::array()}};
    int64_t rendered = 0, skipped = 0, failed = 0, empty_frames = 0;
    std::vector<double> frame_seconds;   // of the frames rendered, in order: the time left comes from them
    FrameSet failed_frames, done_frames;   // of those tried
    std::string current;   // "frame 12", for the progress bar's stage
    if (progress) renderer.setStageStart([&](const std::string& stage) { progress->describe(current + ": " + stage); });
    for (int64_t k = 0; k < count; ++k) {
        const std::optional<int> frame = frames ? std::optional<int>(frames->at(k)) : std::nullopt;
        const std::string name = frame ? "frame " + std::to_string(*frame) : "frame";
        nlohmann::json line = {{"frame", frame ? nlohmann::json(*frame) : nlohmann::json()}, {"host", host}, {"pid", getpid()}};
        if (options.resume) {
            const FrameCheck check = checkFrame(scene, frame, hash);
            if (check.state == FrameCheck::State::Done) {
                ++skipped;
                if (frame) done_frames.add(*frame);
                out << "skipped " << name << ": " << check.path << " is done\n";
                line.update({{"status", "skipped"}, {"path", check.path}, {"time", utcNow()}});
                log.write(line);
                if (progress) progress->advance();
                continue;
            }
        }
        current = name;
        const auto start = std::chrono::steady_clock::now();
        bool frame_failed = false;
        try {
            const FrameResult r = renderer.renderToFile(frame, frames.has_value());
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            clearProgressLine();
            ++rendered;
            if (frame) done_frames.add(*frame);
            frame_seconds.push_back(seconds);
            for (const auto& w : r.warnings) err << "voxlux: warning: " << w << "\n";
            empty_frames += r.empty;
            out << "wrote " << writtenFilesText(r) << " (" << renderer.backendName() << ", " << r.bricks << " bricks)";
            nlohmann::json stages = nlohmann::json::object();
            double total = 0;
            char text[64];
            for (const auto& [stage, s] : r.stage_seconds) {
                std::snprintf(text, sizeof text, "  %s %.3f s", stage.c_str(), s);
                out << text;
                stages[stage] = s;
                total += s;
            }
            out << "\n";
            nlohmann::json fj = {{"stages", stages}, {"total_seconds", total}, {"bricks", r.bricks},
                                 {"atlas_bytes", r.atlas_bytes}, {"empty", r.empty}};
            if (frame) fj["frame"] = *frame;
            stats["frames"].push_back(fj);
            line.update({{"status", "rendered"}, {"path", r.path}, {"seconds", seconds}, {"stages", stages},
                         {"reused", r.reused}, {"warnings", r.warnings}, {"empty", r.empty}});
        } catch (const Interrupted&) {
            throw;
        } catch (const std::exception& e) {
            const bool input = dynamic_cast<const InputError*>(&e) != nullptr;
            const std::string message = (input ? "" : "internal error: ") + std::string(e.what());
            line.update({{"status", "failed"}, {"error", message}, {"time", utcNow()}});
            log.write(line);
            if (!frames) throw;   // one file: the render's error, as ever
            clearProgressLine();
            ++failed;
            failed_frames.add(*frame);
            err << "voxlux: error: " << name << ": " << message << "\n";
            frame_failed = true;
        }
        if (frame_failed && options.fail_fast) break;
        if (!frame_failed) {   // outside the frame's try: a log that cannot be written stops the run
            line["time"] = utcNow();
            log.write(line);
        }
        if (progress) {
            progress->advance();
            if (rendered) progress->estimateLeft(sequenceSecondsLeft(frame_seconds, count - k - 1));
        }
    }
    if (empty_frames) err << "voxlux: warning: " << empty_frames << " empty frame(s) rendered transparent\n";
    if (skipped) out << "resumed: " << skipped << " of " << count << " frames were done and skipped\n";
    stats["peak_rss_bytes"] = peakRssBytes();
    if (options.stats) writeFileAtomically(*options.stats, jsonText(stats, 2) + "\n");
    if (!failed && !missing.count()) return 0;
    const int64_t unrendered = count - rendered - skipped - failed;
    // Stopped by --fail-fast, the frames failed are those tried; else every frame asked for but done.
    const FrameSet failures = unrendered ? failed_frames : requested->notAmong(done_frames);
    err << "voxlux: error: " << failures.count() << " of " << requested->count() << " frames failed: " << failures.text()
        << (unrendered ? " (stopped there, --fail-fast; " + std::to_string(unrendered) + " not rendered)" : "") << "\n";
    return kFramesFailed;
}

}  // namespace voxlux
