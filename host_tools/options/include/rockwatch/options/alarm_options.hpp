// The engine options shared by simulate and study: --arith fixed|double (the engine's arithmetic) and the instability
// alarm, --alarms with --lambda-w, --alarm-hold, --energy-margin, --imminent-horizon and --energy-min-x
// (core::AlarmSettings),
// validated with messages that name the option at fault. rockwatch-monitor registers and checks the alarm settings
// with the same functions.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/options/cli11_fwd.hpp"

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::options {

struct AlarmOptionTexts {
  std::string arith = "double";
  bool alarms = false;
  std::string lambda_w, hold, margin, horizon, energy_min_x;
  std::string work_overflow;  // --work-overflow (fixed point with --alarms: the publication's measurement)
};

// The alarm settings' ranges (core::AlarmSettings): lambda_w in (0, 1], the hold in [0, kMaxAlarmHold_s] s, the
// energy margin in [kMinEnergyMargin, kMaxEnergyMargin], the look-ahead horizon in [0, kMaxImminentHorizon_s] s
// (0: off; core::imminent_horizon_valid).
inline constexpr double kMaxAlarmHold_s = 3600.0;
inline constexpr double kMinEnergyMargin = 1.0;
inline constexpr double kMaxEnergyMargin = 100.0;
inline constexpr double kMaxImminentHorizon_s = 10.0;

// The one check of each setting, for the command lines of `rockwatch simulate`, `rockwatch study` and
// rockwatch-monitor and the monitor's configuration file: throws UsageError "<name> must be <range> (got <value>)".
void check_lambda_w(const std::string& name, double value);
void check_alarm_hold(const std::string& name, double value);
void check_energy_margin(const std::string& name, double value);
void check_imminent_horizon(const std::string& name, double value);  // core::imminent_horizon_valid
void check_energy_min_x(const std::string& name, double value);      // core::energy_min_x_valid
// The ranges as the messages say them: "in (0, 1], a fraction of x_inst", "in [0, 3600] s", ...
std::string lambda_w_range_text();
std::string alarm_hold_range_text();
std::string energy_margin_range_text();
std::string imminent_horizon_range_text();
std::string energy_min_x_range_text();

// Registers --lambda-w, --alarm-hold, --energy-margin, --imminent-horizon and --energy-min-x, in that order, their
// help starting with `help_prefix` ("With --alarms: " in the tool; "" in the monitor, whose alarm always runs) and
// stating core::AlarmSettings's defaults.
void add_alarm_setting_options(CLI::App& app, AlarmOptionTexts& texts, const std::string& help_prefix);

// Registers --arith, --alarms, --lambda-w, --alarm-hold, --energy-margin, --imminent-horizon, --energy-min-x and
// --work-overflow, in that order.
void add_alarm_options(CLI::App& app, AlarmOptionTexts& texts);

// The same options as values: what the command line's texts convert to (alarm_option_values), or what a program sets
// itself (the Python module's keywords). A setting not given is none.
struct AlarmOptionValues {
  std::string arith = "double";                // --arith: double | fixed
  bool alarms = false;                         // --alarms
  std::optional<double> lambda_w, hold_s, energy_margin;  // --lambda-w, --alarm-hold, --energy-margin
  std::optional<double> imminent_horizon_s;    // --imminent-horizon
  std::optional<double> energy_min_x;          // --energy-min-x
  std::optional<std::string> work_overflow;    // --work-overflow: shed | finish
};

// The options given on the command line, their numbers converted (UsageError naming the option when not a number).
AlarmOptionValues alarm_option_values(const CLI::App& app, const AlarmOptionTexts& texts);

// Sets options.arithmetic, evaluate_alarm, alarm, and work_budget_units and work_overflow (the firmware's, with
// --arith fixed --alarms). The alarm settings without --alarms, --work-overflow without --arith fixed --alarms,
// --arith fixed with a model other than linear (set options.model first) and values out of range throw UsageError
// naming the option. The one check of these options, for the command lines and the Python module.
void apply_alarm_options(const AlarmOptionValues& values, sim::AnalysisOptions& options);

// apply_alarm_options(alarm_option_values(app, texts), options).
void parse_alarm_options(const CLI::App& app, const AlarmOptionTexts& texts, sim::AnalysisOptions& options);

// The rules of issue 40 that are on (the look-ahead horizon, the energy rule's displacement), a sentence each, for the
// text reports of simulate and study: empty when both are 0 (the defaults before 2026-12-01).
std::vector<std::string> opt_in_alarm_rule_texts(const core::AlarmSettings& s);

// "double" | "fixed".
const char* arithmetic_name(sim::Arithmetic arithmetic);

// The alarm_reason bits by name, in bit order ("moving", "energy_over_barrier_outward", ...; "bitN" for a bit this
// tool does not know), and the same joined with ", " ("none" for 0).
std::vector<std::string> alarm_reason_list(std::uint32_t reasons);
std::string alarm_reason_names(std::uint32_t reasons);

}  // namespace rockwatch::options
