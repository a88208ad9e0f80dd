// Helpers of the live tests of test_monitor (test_monitor_live.cpp, test_monitor_faults.cpp): real rockwatch-monitor
// processes on UDP multicast on loopback, with channel names of this test process's own.
#pragma once

#include <sys/types.h>  // pid_t

#include <string>
#include <vector>

#include "cli_process.hpp"  // TempDir

namespace rockwatch::test {

void sleep_s(double seconds);
double now_s();  // CLOCK_MONOTONIC [s]

// The monitor's five channels, named PREFIX_ACCEL ... PREFIX_STATUS with this process's pid (unique_channel).
struct LiveChannels {
  explicit LiveChannels(const std::string& prefix);
  std::string accel, batch, state, alarm, status;
};

// udpm multicast on a port of this test process's own (other test runs on the machine use theirs), ttl=0. Offsets 0
// and 1 are two ports (tests that run a monitor while another may still be winding down use the other one).
int live_test_port(int offset);
std::string live_test_url(int offset);

// True (and a "SKIPPED" line printed) when multicast on `url` does not come back to this process: no route on
// loopback, or LCM cannot start with it. The live tests return at once then.
bool skip_without_multicast(const std::string& url);

// DIR/FILE_NAME: a configuration file naming the channels.
std::string write_channels_config(const TempDir& dir, const LiveChannels& c, const std::string& file_name);

// Starts the monitor with `arguments`, stdout and stderr to the files named, and waits until it says it listens;
// fails the test (after killing it) when it exits or does not within 20 s.
pid_t start_monitor_listening(const std::vector<std::string>& arguments, const std::string& out_path,
                              const std::string& err_path);

}  // namespace rockwatch::test
