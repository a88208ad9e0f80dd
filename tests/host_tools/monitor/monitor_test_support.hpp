// Helpers of test_monitor: run `rockwatch-monitor` and the log generator as processes, read what they wrote, decode
// an output log with the lcm-gen types.
#pragma once

#include <sys/types.h>  // pid_t

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"  // ProcessResult, run_program, spawn_program, TempDir, EnvOverride, wait_status
#include "rockwatch/alarm_event_t.hpp"
#include "rockwatch/monitor_status_t.hpp"
#include "rockwatch/wall_state_t.hpp"

namespace rockwatch::test {

ProcessResult run_monitor(const std::vector<std::string>& arguments);
pid_t spawn_monitor(const std::vector<std::string>& arguments, const std::string& out_path,
                    const std::string& err_path);

std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& text);

// Each non-empty line parsed as JSON. Throws std::runtime_error naming the line that is not JSON.
std::vector<nlohmann::json> json_lines(const std::string& text);

// The shipped input log and its golden output (tests/data/monitor/).
std::string monitor_data_path(const std::string& name);
inline constexpr const char* kShippedLog = "set01_X_0.40g_200Hz.lcmlog";
inline constexpr const char* kGoldenFile = "set01_X_0.40g_200Hz.golden.json";

// An output log of the monitor, decoded. Throws std::runtime_error for an event that does not decode.
struct OutputLog {
  struct Timed {
    std::int64_t event_utime;  // the log event's timestamp
  };
  struct State : Timed {
    rockwatch::wall_state_t message;
  };
  struct Alarm : Timed {
    rockwatch::alarm_event_t message;
  };
  struct Status : Timed {
    rockwatch::monitor_status_t message;
  };
  std::vector<State> states;
  std::vector<Alarm> alarms;
  std::vector<Status> statuses;
  std::vector<std::string> other_channels;  // events on channels that are none of the three
  std::uint64_t state_digest = 0;           // FNV-1a 64 over every wall_state event: timestamp and encoded bytes
  std::int64_t events = 0;
};
OutputLog read_output_log(const std::string& path);

// A channel name no other process on this machine uses (this test process's pid in it).
std::string unique_channel(const std::string& base);

}  // namespace rockwatch::test
