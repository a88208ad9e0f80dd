// rockwatch-monitor's command line: the options as typed (RawOptions), their registration with the help text, the
// parse that turns CLI11's errors into UsageError, and the arithmetic's names. Part of the settings
// (monitor_config.hpp), which merge these with the configuration file (monitor_config_file.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rockwatch/options/cli11_fwd.hpp"

#include "monitor_config.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/observer_options.hpp"
#include "rockwatch/options/realtime_options.hpp"
#include "rockwatch/options/wall_options.hpp"

namespace rockwatch::monitor::config_detail {

struct RawOptions {
  std::string config, lcm_url, arith = "fixed", rate, max_step, offline_in, offline_out, log, receive_path = "own";
  std::string clock_tolerance;
  std::string forecast, forecast_rate;  // --forecast N,H; --forecast-rate HZ
  std::string forecast_calibration;     // --forecast-calibration C0,C1,C2,C3[,C4]
  std::string work_budget, work_overflow;
  std::vector<std::string> accept_from;
  options::RealtimeOptionTexts timing;  // --realtime, --cpu, --busy-poll-us
  options::WallOptionTexts wall;
  std::string r = "exp", model = "linear", kappa;
  // --lambda-w, --alarm-hold, --energy-margin, --imminent-horizon, --energy-min-x (its arith and alarms are unused)
  options::AlarmOptionTexts alarm;
  bool print_config = false, version = false, observer = false;
};

void add_options(CLI::App& app, RawOptions& raw);
// The help text when --help was given; throws UsageError for a CLI11 parse error.
std::optional<std::string> parse_arguments(CLI::App& app, int argc, const char* const* argv);
firmware::MonitorArithmetic parse_arith(const std::string& name, const std::string& text);
const char* arith_name(firmware::MonitorArithmetic a);

}  // namespace rockwatch::monitor::config_detail
