// What `rockwatch-monitor` prints: one JSON line per alarm transition on stdout (flushed at once, for a supervisor
// reading the pipe), and at the end a {"summary": {...}} line on stdout and a human summary on stderr.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"

namespace rockwatch::monitor {

// {"utime", "seq", "input_seq", "level", "previous", "reason": [names], "reason_bits", "x_m", "xd_mps",
//  "energy_ratio", "t_to_instability_s" (null for −1: the wall would turn back)}
nlohmann::json alarm_json(const rockwatch::alarm_event_t& event);

// "QUIET" ... "COLLAPSED"; "LEVEL<n>" for a value this build does not know.
std::string level_name(std::int64_t level);

// Every MonitorCounters field by name.
nlohmann::json counters_json(const firmware::MonitorCounters& counters);
// The summary's "observer" object (with the observer only): its settings, the last estimates and its counters.
nlohmann::json observer_json(const core::ObserverOptions& options, const core::ObserverSample& last,
                             const core::ObserverCounters& counters, const firmware::MonitorCounters& loop);

// The listener the executable installs: prints each alarm event and remembers the highest level.
class AlarmPrinter final : public firmware::MonitorListener {
 public:
  // wall: with many walls, the wall's name, added to each line as "wall".
  explicit AlarmPrinter(std::ostream& out, std::string wall = {}) : out_(out), wall_(std::move(wall)) {}
  void on_alarm(const rockwatch::alarm_event_t& event) override;
  std::int64_t events() const { return events_; }
  std::int64_t max_level() const { return max_level_; }

 private:
  std::ostream& out_;
  std::string wall_;
  std::int64_t events_ = 0;
  std::int64_t max_level_ = 0;
};

}  // namespace rockwatch::monitor
