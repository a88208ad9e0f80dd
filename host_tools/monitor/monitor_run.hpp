// `rockwatch-monitor`: parse the settings, start the monitor loop on LCM (live) or on an LCM log (offline), print the
// alarm transitions and the summary. SIGINT/SIGTERM stop it cleanly (final status, summary, exit 0).
#pragma once

#include <ostream>

namespace rockwatch::monitor {

inline constexpr int kExitOk = 0;
inline constexpr int kExitRuntime = 1;  // LCM failed while running, the output log could not be written
inline constexpr int kExitUsage = 2;    // invalid options, configuration or files: nothing started

// The whole program; `out` gets the JSON lines, `err` the messages and the human summary.
int run_monitor(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace rockwatch::monitor
