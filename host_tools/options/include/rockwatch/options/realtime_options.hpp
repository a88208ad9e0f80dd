// The timing options of a program with a timing-critical thread: --realtime PRIO (SCHED_FIFO for that thread and its
// memory locked), --cpu N (the thread pinned to one CPU) and --busy-poll-us US (SO_BUSY_POLL on its receive socket).
// rockwatch-monitor registers them (and reads the same settings from its configuration file); what they ask of Linux
// is rockwatch/process/realtime.hpp. Declared here once, with one range check each whose message names the option or
// the configuration key, so a command line and a file are refused alike.
#pragma once

#include <string>

#include "rockwatch/options/cli11_fwd.hpp"

namespace rockwatch::options {

struct RealtimeOptionTexts {
  std::string realtime, cpu, busy_poll_us;
};

inline constexpr int kMaxBusyPoll_us = 100000;  // 100 ms: more is a spinning thread, not a poll

// Registers --realtime, --cpu and --busy-poll-us; `thread` names what they apply to ("the receive and processing
// thread").
void add_realtime_options(CLI::App& app, RealtimeOptionTexts& texts, const std::string& thread);

// Each takes the value as given on the command line (`text`) and throws UsageError "NAME: expected ..., got TEXT".
int parse_realtime_priority(const std::string& name, const std::string& text);
int parse_cpu(const std::string& name, const std::string& text);
int parse_busy_poll_us(const std::string& name, const std::string& text);

// The same checks for a whole number read elsewhere (a configuration file): the value when valid, else UsageError.
// A priority in [min, max] of SCHED_FIFO (1..99); a CPU this process may run on (its affinity mask, `taskset -p`);
// a busy-poll time in [1, kMaxBusyPoll_us] µs.
int check_realtime_priority(const std::string& name, long long value);
int check_cpu(const std::string& name, long long value);
int check_busy_poll_us(const std::string& name, long long value);

}  // namespace rockwatch::options
