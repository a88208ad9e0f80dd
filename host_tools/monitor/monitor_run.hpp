// `rockwatch-monitor`: parse the settings, start the monitor loop on LCM (live) or on an LCM log (offline), print the
// alarm transitions and the summary. SIGINT/SIGTERM stop it cleanly (final status, summary, exit 0).
#pragma once

#include <functional>
#include <memory>
#include <ostream>

namespace lcm {
class LCM;
}  // namespace lcm

namespace rockwatch::monitor {

inline constexpr int kExitOk = 0;
inline constexpr int kExitRuntime = 1;  // LCM failed while running, the output log could not be written
inline constexpr int kExitUsage = 2;    // invalid options, configuration or files: nothing started

// What the monitor's messages on stderr start with.
inline constexpr const char* kMessagePrefix = "rockwatch-monitor: ";

class LiveInput;  // monitor_input_source.hpp
// Makes the live input of --receive-path liblcm on the monitor's publishing LCM instance. Only the benchmark's build
// has one (tests/bench/lcm_input_source.hpp): the monitor's own program reads its input with its own checked path.
using LiblcmInputFactory = std::function<std::unique_ptr<LiveInput>(lcm::LCM& lcm)>;

// The whole program; `out` gets the JSON lines, `err` the messages and the human summary. `liblcm`: the input of
// --receive-path liblcm (null: that path is refused).
int run_monitor(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
                const LiblcmInputFactory* liblcm = nullptr);

}  // namespace rockwatch::monitor
