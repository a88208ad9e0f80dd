// The version of the `rockwatch` tool, for what it writes into its outputs (the generator field of suite files).
#pragma once

namespace rockwatch::cli {

// The project version (CMake's PROJECT_VERSION), e.g. "0.1.0".
const char* tool_version();

}  // namespace rockwatch::cli
