// The repository's folder, for the shared data beside it (../shared/data): from a file CMake
// generates, so that no benchmark's compile line holds an absolute path and a clone in another
// folder hits ccache.
#pragma once
#include <string>

namespace voxlux::bench {

std::string sourceDir();

}  // namespace voxlux::bench
