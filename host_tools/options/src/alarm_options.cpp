#include "rockwatch/options/alarm_options.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/core/sample_engine.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::options {

namespace {

std::string range_closed(double low, double high) { return "[" + number_text(low) + ", " + number_text(high) + "]"; }

}  // namespace

std::string lambda_w_range_text() { return "in (0, 1], a fraction of x_inst"; }
std::string alarm_hold_range_text() { return "in " + range_closed(0.0, kMaxAlarmHold_s) + " s"; }
std::string energy_margin_range_text() {
  return "in " + range_closed(kMinEnergyMargin, kMaxEnergyMargin) + ", a multiple of the energy barrier";
}
std::string imminent_horizon_range_text() { return "in " + range_closed(0.0, kMaxImminentHorizon_s) + " s"; }
std::string energy_min_x_range_text() { return "in [0, 1], a fraction of x_inst"; }

void check_lambda_w(const std::string& name, double value) {
  if (!(value > 0.0 && value <= 1.0)) {
    throw UsageError(name + " must be " + lambda_w_range_text() + " (got " + number_text(value) + ")");
  }
}

void check_alarm_hold(const std::string& name, double value) {
  if (!(value >= 0.0 && value <= kMaxAlarmHold_s)) {
    throw UsageError(name + " must be " + alarm_hold_range_text() + " (got " + number_text(value) + ")");
  }
}

void check_energy_margin(const std::string& name, double value) {
  if (!(value >= kMinEnergyMargin && value <= kMaxEnergyMargin)) {
    throw UsageError(name + " must be " + energy_margin_range_text() + " (got " + number_text(value) + ")");
  }
}

void check_imminent_horizon(const std::string& name, double value) {
  if (!core::imminent_horizon_valid(value)) {
    throw UsageError(name + " must be " + imminent_horizon_range_text() + " (got " + number_text(value) + ")");
  }
}

void check_energy_min_x(const std::string& name, double value) {
  if (!core::energy_min_x_valid(value)) {
    throw UsageError(name + " must be " + energy_min_x_range_text() + " (got " + number_text(value) + ")");
  }
}

void add_alarm_setting_options(CLI::App& app, AlarmOptionTexts& texts, const std::string& help_prefix) {
  const core::AlarmSettings defaults{};
  // After a prefix the sentence goes on in lower case; without one it starts with a capital.
  const std::string time_the = help_prefix.empty() ? "Time the" : help_prefix + "time the";
  app.add_option("--lambda-w", texts.lambda_w,
                 help_prefix + "WARNING when |x| >= lambda_w * x_inst, 0 < lambda_w <= 1 (default " +
                     number_text(defaults.lambda_warning) + ")")
      ->type_name("X");
  app.add_option("--alarm-hold", texts.hold,
                 time_the + " conditions must stay below a level before it falls [s], 0 to " +
                     number_text(kMaxAlarmHold_s) + " (default " + number_text(defaults.hold_s) + ")")
      ->type_name("S");
  app.add_option("--energy-margin", texts.margin,
                 help_prefix + "IMMINENT when E >= M * E_barrier moving outward, " + number_text(kMinEnergyMargin) +
                     " <= M <= " + number_text(kMaxEnergyMargin) + " (default " +
                     number_text(defaults.energy_margin) + ")")
      ->type_name("M");
  app.add_option("--imminent-horizon", texts.horizon,
                 help_prefix + "IMMINENT also when E >= E_barrier moving outward and the predicted time to x_inst "
                     "under no further input is at most S [s], 0 (off) to " + number_text(kMaxImminentHorizon_s) +
                     " (default " + number_text(defaults.imminent_horizon_s) + ")")
      ->type_name("S");
  app.add_option("--energy-min-x", texts.energy_min_x,
                 help_prefix + "IMMINENT by the energy margin only once |x| >= F * x_inst, 0 (everywhere) to 1 "
                     "(default " + number_text(defaults.energy_min_x) + "; SPEC 11: fewer false alarms, less lead)")
      ->type_name("F");
}

void add_alarm_options(CLI::App& app, AlarmOptionTexts& texts) {
  app.add_option("--arith", texts.arith,
                 "Engine arithmetic: double (default, the verified engine) | fixed (the monitor's fixed-point engine; "
                 "linear model only)")
      ->type_name("fixed|double");
  app.add_flag("--alarms", texts.alarms,
               "Run the instability alarm (QUIET, ROCKING, WARNING, IMMINENT, COLLAPSED) after every integration step");
  add_alarm_setting_options(app, texts, "With --alarms: ");
  app.add_option("--work-overflow", texts.work_overflow,
                 "With --arith fixed --alarms, what the firmware's budgeted engine does when its queue of waiting "
                 "samples is full, for the publication measured beside the answers: shed (default; every call within "
                 "its budget, the shed samples' events not located) | finish (the oldest sample finished beyond the "
                 "budget: the answers always published as computed)")
      ->type_name("shed|finish");
}

AlarmOptionValues alarm_option_values(const CLI::App& app, const AlarmOptionTexts& texts) {
  AlarmOptionValues v;
  v.arith = texts.arith;
  v.alarms = texts.alarms;
  if (given(app, "--work-overflow")) v.work_overflow = texts.work_overflow;
  if (given(app, "--lambda-w")) v.lambda_w = parse_finite_number("--lambda-w", texts.lambda_w);
  if (given(app, "--alarm-hold")) v.hold_s = parse_finite_number("--alarm-hold", texts.hold);
  if (given(app, "--energy-margin")) v.energy_margin = parse_finite_number("--energy-margin", texts.margin);
  if (given(app, "--imminent-horizon")) {
    v.imminent_horizon_s = parse_finite_number("--imminent-horizon", texts.horizon);
  }
  if (given(app, "--energy-min-x")) v.energy_min_x = parse_finite_number("--energy-min-x", texts.energy_min_x);
  return v;
}

void apply_alarm_options(const AlarmOptionValues& v, sim::AnalysisOptions& options) {
  if (v.arith == "double") {
    options.arithmetic = sim::Arithmetic::double_precision;
  } else if (v.arith == "fixed") {
    options.arithmetic = sim::Arithmetic::fixed_point;
    if (options.model != core::ModelKind::linear) {
      throw UsageError("--arith fixed supports the linear model only (got --model " +
                       std::string(model_name(options.model)) + ")");
    }
  } else {
    throw UsageError("--arith must be fixed or double (got " + quoted(v.arith) + ")");
  }

  options.evaluate_alarm = v.alarms;
  // The fixed engine's alarm as the monitor publishes it: its budget per call (docs/FIXED_POINT.md "carry-over").
  options.work_budget_units =
      options.arithmetic == sim::Arithmetic::fixed_point && v.alarms ? core::kDefaultWorkBudgetUnits : 0;
  if (v.work_overflow) {
    if (options.work_budget_units == 0) {
      throw UsageError("--work-overflow applies to the firmware's publication, measured with --arith fixed --alarms");
    }
    options.work_overflow = parse_work_overflow("--work-overflow", *v.work_overflow);
  }
  const std::pair<const char*, const std::optional<double>*> settings[] = {
      {"--lambda-w", &v.lambda_w}, {"--alarm-hold", &v.hold_s}, {"--energy-margin", &v.energy_margin},
      {"--imminent-horizon", &v.imminent_horizon_s}, {"--energy-min-x", &v.energy_min_x}};
  for (const auto& [option, value] : settings) {
    if (value->has_value() && !v.alarms) {
      throw UsageError(std::string(option) + " sets the instability alarm: give --alarms too");
    }
    if (value->has_value()) check_finite_number(option, **value);
  }
  core::AlarmSettings& a = options.alarm;
  if (v.lambda_w) {
    a.lambda_warning = *v.lambda_w;
    check_lambda_w("--lambda-w", a.lambda_warning);
  }
  if (v.hold_s) {
    a.hold_s = *v.hold_s;
    check_alarm_hold("--alarm-hold", a.hold_s);
  }
  if (v.energy_margin) {
    a.energy_margin = *v.energy_margin;
    check_energy_margin("--energy-margin", a.energy_margin);
  }
  if (v.imminent_horizon_s) {
    a.imminent_horizon_s = *v.imminent_horizon_s;
    check_imminent_horizon("--imminent-horizon", a.imminent_horizon_s);
  }
  if (v.energy_min_x) {
    a.energy_min_x = *v.energy_min_x;
    check_energy_min_x("--energy-min-x", a.energy_min_x);
  }
}

std::vector<std::string> opt_in_alarm_rule_texts(const core::AlarmSettings& s) {
  std::vector<std::string> texts;
  if (s.imminent_horizon_s > 0.0) {
    texts.push_back("IMMINENT also at E >= E_barrier moving outward with x_inst predicted within " +
                    number_text(s.imminent_horizon_s) + " s");
  }
  if (s.energy_min_x > 0.0) {
    texts.push_back("IMMINENT by the energy margin only from |x| >= " + number_text(s.energy_min_x) + " x_inst");
  }
  return texts;
}

void parse_alarm_options(const CLI::App& app, const AlarmOptionTexts& texts, sim::AnalysisOptions& options) {
  apply_alarm_options(alarm_option_values(app, texts), options);
}

const char* arithmetic_name(sim::Arithmetic arithmetic) {
  return arithmetic == sim::Arithmetic::fixed_point ? "fixed" : "double";
}

std::vector<std::string> alarm_reason_list(std::uint32_t reasons) {
  namespace bit = core::alarm_reason;
  const struct {
    std::uint32_t bit;
    const char* name;
  } names[] = {{bit::moving, "moving"},
               {bit::over_warning_displacement, "over_warning_displacement"},
               {bit::energy_over_barrier_outward, "energy_over_barrier_outward"},
               {bit::over_instability_displacement, "over_instability_displacement"},
               {bit::over_collapse_displacement, "over_collapse_displacement"},
               {bit::held, "held"},
               {bit::input_invalid, "input_invalid"},
               {bit::arithmetic_saturated, "arithmetic_saturated"},
               {bit::measured, "measured"},
               {bit::predicted, "predicted"},
               {bit::sensor_fault, "sensor_fault"}};
  std::vector<std::string> list;
  std::uint32_t known = 0;
  for (const auto& n : names) {
    known |= n.bit;
    if ((reasons & n.bit) != 0) list.emplace_back(n.name);
  }
  for (int b = 0; b < 32; ++b) {
    const std::uint32_t mask = std::uint32_t{1} << b;
    if ((reasons & mask & ~known) != 0) list.push_back("bit" + std::to_string(b));  // a reason newer than this tool
  }
  return list;
}

std::string alarm_reason_names(std::uint32_t reasons) {
  std::string text;
  for (const std::string& name : alarm_reason_list(reasons)) text += (text.empty() ? "" : ", ") + name;
  return text.empty() ? std::string("none") : text;
}

}  // namespace rockwatch::options
