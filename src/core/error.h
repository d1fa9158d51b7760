// voxlux reports every user-facing failure as one line: "<file>: <problem>".
#pragma once
#include <stdexcept>
#include <string>

namespace voxlux {

// Bad input from the user (files, scene, options). main() prints what() and exits with kInputError.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

constexpr int kInputError = 2;
constexpr int kInternalError = 1;

}  // namespace voxlux
