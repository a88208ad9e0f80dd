// The summary a monitor run ends with, written once for every mode: a {"summary": {...}} line on stdout (the walls'
// counters and alarms, the statuses published, why the loop stopped, the input's and the mode's own fields, the
// forecasts) and a human summary on stderr.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "monitor_config.hpp"
#include "monitor_forecast.hpp"
#include "monitor_wall_set.hpp"

namespace rockwatch::monitor {

// What the summary says beyond the walls: `fields` (the mode, the input's and the mode's own keys), the loop's
// statuses and why it stopped, the human summary's first line and its last lines (`human_tail`, may be empty).
struct SummaryParts {
  nlohmann::json fields = nlohmann::json::object();
  std::int64_t statuses = 0;
  std::string stopped_by;
  std::string first_line;
  const MonitorForecaster* forecaster = nullptr;  // with --forecast
  std::string human_tail;
};

void write_summary(std::ostream& out, std::ostream& err, const MonitorConfig& config, MonitorWalls& walls,
                   const SummaryParts& parts);

}  // namespace rockwatch::monitor
