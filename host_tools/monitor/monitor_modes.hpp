// The two ways rockwatch-monitor runs its one loop (monitor_event_loop.hpp), once the settings are checked: each
// sets up its input, clock, outputs and services, runs the loop, and adds its own fields to the summary.
#pragma once

#include <ostream>

#include "monitor_config.hpp"
#include "monitor_run.hpp"

namespace rockwatch::monitor {

// Live (monitor_live.cpp): LCM in through the monitor's own UDP path (or `liblcm`'s, the benchmark's), LCM out,
// on the machine's clocks, until SIGINT/SIGTERM.
int run_live(const MonitorConfig& config, const LiblcmInputFactory* liblcm, std::ostream& out, std::ostream& err);

// Offline (monitor_offline.cpp): an LCM log in, an LCM log out, in log time: the same input, the same bytes out.
int run_offline(const MonitorConfig& config, std::ostream& out, std::ostream& err);

}  // namespace rockwatch::monitor
