// Progress of long jobs, and Ctrl-C. Library code (reference renders, study phases, sequences)
// reports units of work through a ProgressTask; the command line chooses what is shown: a bar
// with the time left on a terminal, a line at a steady rate with --progress, or nothing (the
// default for a library user). Tasks nest: the bar shows the outer one (a study's 12/40) and the
// inner one (that render's samples). Costs an atomic add per advance(); the display is redrawn at
// most every 0.1 s (bar) by whichever thread advances then; lines come every interval from a ticker
// thread, whatever the job is doing, and the outermost task's last line says it is done.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <stdexcept>
#include <string>

namespace voxlux {

enum class ProgressDisplay { Off, Bar, Lines };

// Where and how progress shows; `line_seconds` is the interval of Lines.
void setProgressDisplay(ProgressDisplay display, std::ostream& out, double line_seconds = 10.0);

// Clears the bar before other output to the same terminal; the next advance redraws it.
void clearProgressLine();

// Ctrl-C (SIGINT, and SIGTERM as a farm's scheduler sends it): the first one asks the job to stop
// at the next advance(), which throws Interrupted; outputs are only ever renamed into place
// whole, so nothing is left half-written. A second one ends the process at once.
void installInterruptHandler();
struct Interrupted : std::runtime_error {
    Interrupted() : std::runtime_error("interrupted") {}
};
// Throws Interrupted once a stop was asked for.
void throwIfInterrupted();
// The signal that asked to stop (SIGINT or SIGTERM), 0 while none did: a loop that never calls
// advance() (the viewer's) polls it, and the process exits with 128 + it, as a shell reports.
int interruptSignal();

class ProgressTask {
public:
    // `unit` names what is counted ("samples", "frames").
    ProgressTask(std::string label, int64_t total, std::string unit);
    ~ProgressTask();
    ProgressTask(const ProgressTask&) = delete;
    ProgressTask& operator=(const ProgressTask&) = delete;

    // Thread-safe. Throws Interrupted after Ctrl-C.
    void advance(int64_t units = 1);
    // What is being done now, shown after the counts ("ground truth, half 1 of 2").
    void describe(std::string what);
    // A better estimate of the time left than elapsed x left / done, when the job has one; < 0:
    // none. It counts down as time passes until the next estimate.
    void estimateLeft(double seconds);

private:
    friend struct ProgressState;
    std::string text(std::chrono::steady_clock::time_point now) const;

    std::string label_, unit_, what_;
    int64_t total_;
    std::atomic<int64_t> done_{0};
    double left_ = -1.0;                                   // estimateLeft's, counting down from left_since_
    std::chrono::steady_clock::time_point left_since_{};
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    ProgressTask* outer_ = nullptr;
};

// "1m02s", "2h05m".
std::string clockText(double seconds);

}  // namespace voxlux
