#include "common/process/tool_version.hpp"

// Set for the CLI library by host_tools/CMakeLists.txt, like the executable's; "unknown" only in a build that bypasses it.
#ifndef ROCKWATCH_VERSION
#define ROCKWATCH_VERSION "unknown"
#endif

namespace rockwatch::cli {

const char* tool_version() { return ROCKWATCH_VERSION; }

}  // namespace rockwatch::cli
