// Timing of the live receive thread (--realtime, --cpu, --busy-poll-us; config realtime_priority, cpu,
// busy_poll_us): what the settings request, asked for once the monitor is set up and before its input starts.
#pragma once

#include <memory>
#include <ostream>

#include <nlohmann/json.hpp>

#include "monitor_config.hpp"
#include "monitor_input_source.hpp"
#include "rockwatch/process/realtime.hpp"

namespace rockwatch::monitor {

// Asks for what the settings request, for this (the receive and processing) thread and the input's socket; a
// refusal is a warning on `err`, never a failure: the monitor goes on as it would without the option. `report`:
// the summary's "timing". Null when nothing is requested.
std::unique_ptr<process::RealtimeConditions> apply_timing(const TimingSettings& t, LiveInput& input,
                                                          nlohmann::json& report, std::ostream& err);

}  // namespace rockwatch::monitor
