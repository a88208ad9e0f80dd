#include "rockwatch/options/realtime_options.hpp"

#include <sched.h>
#include <unistd.h>

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::options {

namespace {

// The CPUs this process may run on, as text for a message ("0-1", "0,2,5").
std::string allowed_cpus_text(const cpu_set_t& set) {
  std::string text;
  int run_start = -1;
  for (int c = 0; c <= CPU_SETSIZE; ++c) {
    const bool in = c < CPU_SETSIZE && CPU_ISSET(c, &set);
    if (in && run_start < 0) run_start = c;
    if (!in && run_start >= 0) {
      if (!text.empty()) text += ',';
      text += std::to_string(run_start);
      if (c - 1 > run_start) text += "-" + std::to_string(c - 1);
      run_start = -1;
    }
  }
  return text.empty() ? "none" : text;
}

// A plain whole number, so "1.5", "+3", "-1" and "2x" are refused with the option's own message.
long long whole_value(const std::string& name, const std::string& text, const std::string& expected) {
  const std::optional<std::uint64_t> v = whole_number(text, 0, 1000000000);
  if (!v) throw UsageError(name + ": expected " + expected + ", got " + quoted(text));
  return static_cast<long long>(*v);
}

}  // namespace

void add_realtime_options(CLI::App& app, RealtimeOptionTexts& texts, const std::string& thread) {
  app.add_option("--realtime", texts.realtime,
                 "Run " + thread + " under SCHED_FIFO at this priority (1-99) and lock the process's memory "
                 "(mlockall current and future) after start-up. Needs root, CAP_SYS_NICE/CAP_IPC_LOCK or rlimit "
                 "allowances; when refused: a warning, and the monitor goes on with ordinary scheduling")
      ->type_name("PRIO");
  app.add_option("--cpu", texts.cpu,
                 "Pin " + thread + " to this CPU (0 .. the number of CPUs - 1, one this process may run on); "
                 "best with a CPU kept free of other work")
      ->type_name("N");
  app.add_option("--busy-poll-us", texts.busy_poll_us,
                 "SO_BUSY_POLL on the receive socket: busy-wait up to this long for a datagram in the driver before "
                 "sleeping (1-" + std::to_string(kMaxBusyPoll_us) + " us; needs CAP_NET_ADMIN above "
                 "net.core.busy_read; only NICs with NAPI busy polling gain from it, loopback does not)")
      ->type_name("US");
}

int check_realtime_priority(const std::string& name, long long value) {
  const int lo = sched_get_priority_min(SCHED_FIFO), hi = sched_get_priority_max(SCHED_FIFO);
  if (value < lo || value > hi) {
    throw UsageError(name + ": expected a SCHED_FIFO priority in " + std::to_string(lo) + ".." + std::to_string(hi) +
                     ", got " + std::to_string(value));
  }
  return static_cast<int>(value);
}

int check_cpu(const std::string& name, long long value) {
  const long configured = sysconf(_SC_NPROCESSORS_CONF);
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  const bool known = sched_getaffinity(0, sizeof allowed, &allowed) == 0;
  if (value < 0 || value >= CPU_SETSIZE || (configured > 0 && value >= configured)) {
    throw UsageError(name + ": expected a CPU number in 0.." + std::to_string(configured > 0 ? configured - 1 : 0) +
                     " (this machine has " + std::to_string(configured) + "), got " + std::to_string(value));
  }
  if (known && !CPU_ISSET(static_cast<int>(value), &allowed)) {
    throw UsageError(name + ": CPU " + std::to_string(value) + " is not one this process may run on (allowed: " +
                     allowed_cpus_text(allowed) + ")");
  }
  return static_cast<int>(value);
}

int check_busy_poll_us(const std::string& name, long long value) {
  if (value < 1 || value > kMaxBusyPoll_us) {
    throw UsageError(name + ": expected a time in 1.." + std::to_string(kMaxBusyPoll_us) + " us, got " +
                     std::to_string(value));
  }
  return static_cast<int>(value);
}

int parse_realtime_priority(const std::string& name, const std::string& text) {
  return check_realtime_priority(name, whole_value(name, text, "a SCHED_FIFO priority in 1..99"));
}

int parse_cpu(const std::string& name, const std::string& text) {
  return check_cpu(name, whole_value(name, text, "a CPU number (0, 1, ...)"));
}

int parse_busy_poll_us(const std::string& name, const std::string& text) {
  return check_busy_poll_us(name, whole_value(name, text, "a whole number of microseconds"));
}

}  // namespace rockwatch::options
