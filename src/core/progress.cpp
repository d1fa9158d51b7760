#include "core/progress.h"

#include <csignal>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>
#include <ostream>

namespace voxlux {
namespace {

// The signal's number. Lock-free, so the handler may store it; other threads (the viewer's
// watcher, the render's workers) read it.
std::atomic<int> stop_asked{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void onInterrupt(int signal) {
    stop_asked = signal;
    std::signal(signal, SIG_DFL);   // a second one ends the process
}

}  // namespace

struct ProgressState {
    std::mutex mutex;
    ProgressDisplay display = ProgressDisplay::Off;
    std::ostream* out = nullptr;
    double line_seconds = 10.0;
    ProgressTask* innermost = nullptr;
    std::chrono::steady_clock::time_point last_shown{};
    bool bar_drawn = false;

    // Never destroyed: the line ticker (a detached thread) may still read it while the process exits.
    static ProgressState& get() {
        static ProgressState* state = new ProgressState;
        return *state;
    }

    // Called with the mutex held.
    void show(bool force) {
        if (display == ProgressDisplay::Off || !innermost) return;
        const auto now = std::chrono::steady_clock::now();
        const double since = std::chrono::duration<double>(now - last_shown).count();
        // Lines come at a steady rate; the bar also redraws when a task starts or ends.
        if (!(force && display == ProgressDisplay::Bar) && since < (display == ProgressDisplay::Bar ? 0.1 : line_seconds)) return;
        last_shown = now;
        std::string line;
        for (const ProgressTask* t = innermost; t; t = t->outer_) line = t->text(now) + (line.empty() ? "" : "  >  " + line);
        print(line);
    }

    void print(const std::string& line) {
        if (display == ProgressDisplay::Bar) {
            *out << "\r\033[K" << line.substr(0, 150) << std::flush;
            bar_drawn = true;
        } else {
            *out << "voxlux: progress: " << line << "\n" << std::flush;
        }
    }

    void clear() {
        if (bar_drawn) *out << "\r\033[K" << std::flush;
        bar_drawn = false;
    }
};

void clearProgressLine() {
    ProgressState& s = ProgressState::get();
    std::lock_guard<std::mutex> lock(s.mutex);
    s.clear();
}

void setProgressDisplay(ProgressDisplay display, std::ostream& out, double line_seconds) {
    ProgressState& s = ProgressState::get();
    std::lock_guard<std::mutex> lock(s.mutex);
    s.display = display;
    s.out = &out;
    s.line_seconds = line_seconds;
    // Lines come at a steady rate while a long stage runs, not only when work is counted, so a
    // line names the stage that is running (a frame's march), not the one that starts after it.
    static bool ticking = false;
    if (display == ProgressDisplay::Lines && !ticking) {
        ticking = true;
        std::thread([&s] {
            double interval = 0.0;
            for (;;) {
                {
                    std::lock_guard<std::mutex> lock(s.mutex);
                    s.show(false);
                    interval = s.line_seconds;
                }
                std::this_thread::sleep_for(std::chrono::duration<double>(std::max(0.05, interval) / 4.0));
            }
        }).detach();
    }
}

void installInterruptHandler() {
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
}

void throwIfInterrupted() {
    if (stop_asked) throw Interrupted();
}

int interruptSignal() { return stop_asked.load(); }

std::string clockText(double seconds) {
    const long s = std::lround(seconds);
    char buf[32];
    if (s >= 3600) std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, s / 60 % 60);
    else std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
    return buf;
}

ProgressTask::ProgressTask(std::string label, int64_t total, std::string unit)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total) {
    ProgressState& s = ProgressState::get();
    std::lock_guard<std::mutex> lock(s.mutex);
    outer_ = s.innermost;
    s.innermost = this;
    s.show(true);
}

ProgressTask::~ProgressTask() {
    ProgressState& s = ProgressState::get();
    std::lock_guard<std::mutex> lock(s.mutex);
    // The last line of a job's lines says how it ended: the counts done and the time it took.
    if (!outer_ && s.display == ProgressDisplay::Lines) {
        what_ = done_.load() >= total_ ? "done" : "stopped";
        left_ = -1.0;
        s.print(text(std::chrono::steady_clock::now()));
    }
    s.innermost = outer_;
    if (s.innermost) s.show(true);
    else s.clear();
}

void ProgressTask::advance(int64_t units) {
    done_ += units;
    throwIfInterrupted();
    ProgressState& s = ProgressState::get();
    if (s.display == ProgressDisplay::Off) return;
    std::unique_lock<std::mutex> lock(s.mutex, std::try_to_lock);   // another thread is drawing: skip
    if (lock) s.show(false);
}

void ProgressTask::describe(std::string what) {
    ProgressState& s = ProgressState::get();
    std::lock_guard<std::mutex> lock(s.mutex);
    what_ = std::move(what);
    s.show(true);
}

void ProgressTask::estimateLeft(double seconds) {
    ProgressState& s = ProgressState::get();
    std::lock_guard<std::mutex> lock(s.mutex);
    left_ = seconds;
    left_since_ = std::chrono::steady_clock::now();
}

// "[=====>      ] frames 12/60  elapsed 1m02s  left ~3m10s  what"
std::string ProgressTask::text(std::chrono::steady_clock::time_point now) const {
    const int64_t done = std::min<int64_t>(done_.load(), total_);
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double left = left_ >= 0 ? std::max(0.0, left_ - std::chrono::duration<double>(now - left_since_).count())
                        : done > 0 && done < total_ ? elapsed * double(total_ - done) / double(done) : -1.0;
    const int width = 20, filled = total_ > 0 ? int(width * done / total_) : width;
    std::string out = "[" + std::string(size_t(filled), '=') + (filled < width ? ">" : "") +
                      std::string(size_t(std::max(0, width - filled - 1)), ' ') + "] " + label_ + " " +
                      std::to_string(done) + "/" + std::to_string(total_) + " " + unit_ + "  elapsed " + clockText(elapsed);
    if (left >= 0) out += "  left ~" + clockText(left);
    if (!what_.empty()) out += "  " + what_;
    return out;
}

}  // namespace voxlux
