// Runs a scheduler's command-line tool (sbatch, squeue, sacct) and takes its output. No shell:
// arguments go to the program as they are, so a path with spaces or quotes stays one argument.
#pragma once
#include <string>
#include <vector>

namespace voxlux {

struct ProcessResult {
    int exit_code = -1;    // 127 when the program cannot be run (not installed); 128 + N when signal N ended it
    std::string output;    // standard output
    std::string error;     // standard error; for 127, why
};

// The last line of `text` that is not empty ("" if none): what a tool says last.
std::string lastLine(const std::string& text);

ProcessResult runProcess(const std::vector<std::string>& argv);

// `argv` as a POSIX shell reads it back, for messages and --dry-run.
std::string shellCommand(const std::vector<std::string>& argv);
std::string shellQuoted(const std::string& arg);

}  // namespace voxlux
