// Runs a scheduler's command-line tool (sbatch, squeue, sacct) and takes its output. No shell:
// arguments go to the program as they are, so a path with spaces or quotes stays one argument.
#pragma once
#include <string>
#include <vector>

namespace voxlux {

struct ProcessResult {
    int exit_code = -1;    // 127 when the program cannot be run (not installed)
    std::string output;    // standard output and standard error, interleaved as written; for 127, why
};

ProcessResult runProcess(const std::vector<std::string>& argv);

// `argv` as a POSIX shell reads it back, for messages and --dry-run.
std::string shellCommand(const std::vector<std::string>& argv);
std::string shellQuoted(const std::string& arg);

}  // namespace voxlux
