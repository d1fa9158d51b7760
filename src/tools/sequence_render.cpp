#include "tools/sequence_render.h"

#include <unistd.h>

#include <chrono>
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
        std::error_code ec;   // the folder is made as the outputs' are
        if (const auto parent = std::filesystem::path(*path).parent_path(); !parent.empty()) std::filesystem::create_directories(parent, ec);
        file_.open(*path, std::ios::app);
        if (!file_) throw InputError(*path + ": cannot open the log for appending");
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

std::optional<FrameSet> sequenceFrames(const Scene& s) {
    if (!hasFramePattern(s.volume.path)) return std::nullopt;
    if (!s.volume.frames)
        throw InputError(s.volume.path + ": path has a #### frame pattern; set volume.frames or pass --frames");
    const bool several = s.volume.frames->count() > 1;
    if (several && !s.output.path.empty() && !hasFramePattern(s.output.path))
        throw InputError(s.output.path + ": several frames need a #### pattern in the output path");
    if (several && !s.output.preview.empty() && !hasFramePattern(s.output.preview))
        throw InputError(s.output.preview + ": several frames need a #### pattern in the preview path");
    return s.volume.frames;
}

int renderSequence(const Scene& scene, const SequenceOptions& options, std::ostream& out, std::ostream& err) {
    const std::optional<FrameSet> frames = sequenceFrames(scene);
    if (options.stats) checkWritable(*options.stats);   // before any frame: every output or none
    if (const auto problem = outputPathProblem(scene)) throw InputError(*problem);
    FrameLog log(options.log_json);
    const std::string hash = sceneHash(scene), host = hostName();

    Renderer renderer(scene);
    const int64_t count = frames ? frames->count() : 1;
    const auto progress = frames ? std::make_unique<ProgressTask>("sequence", count, "frames") : nullptr;
    nlohmann::json stats = {{"backend", renderer.backendName()}, {"frames", nlohmann::json::array()}};
    int64_t rendered = 0, skipped = 0, failed = 0, empty_frames = 0;
    double render_seconds = 0.0;
    FrameSet failed_frames;
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
            render_seconds += seconds;
            for (const auto& w : r.warnings) err << "voxlux: warning: " << w << "\n";
            empty_frames += r.empty;
            out << "wrote " << r.path << (r.preview_path.empty() ? "" : " and " + r.preview_path) << " ("
                << renderer.backendName() << ", " << r.bricks << " bricks)";
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
            if (rendered) progress->estimateLeft(render_seconds / double(rendered) * double(count - k - 1));
        }
    }
    if (empty_frames) err << "voxlux: warning: " << empty_frames << " empty frame(s) rendered transparent\n";
    if (skipped) out << "resumed: " << skipped << " of " << count << " frames were done and skipped\n";
    stats["peak_rss_bytes"] = peakRssBytes();
    if (options.stats) writeFileAtomically(*options.stats, jsonText(stats, 2) + "\n");
    if (!failed) return 0;
    const int64_t unrendered = count - rendered - skipped - failed;
    err << "voxlux: error: " << failed << " of " << count << " frames failed: " << failed_frames.text()
        << (unrendered ? " (stopped there, --fail-fast; " + std::to_string(unrendered) + " not rendered)" : "") << "\n";
    return kFramesFailed;
}

}  // namespace voxlux
