#include "alarm_options.hpp"

#include <cstdint>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "option_values.hpp"
#include "usage_error.hpp"

namespace rockwatch::cli {

void add_alarm_options(CLI::App& app, AlarmOptionTexts& texts) {
  app.add_option("--arith", texts.arith,
                 "Engine arithmetic: double (default, the verified engine) | fixed (the monitor's fixed-point engine; "
                 "linear model only)")
      ->type_name("fixed|double");
  app.add_flag("--alarms", texts.alarms,
               "Run the instability alarm (QUIET, ROCKING, WARNING, IMMINENT, COLLAPSED) after every integration step");
  app.add_option("--lambda-w", texts.lambda_w,
                 "With --alarms: WARNING when |x| >= lambda_w * x_inst, 0 < lambda_w <= 1 (default 0.4)")
      ->type_name("X");
  app.add_option("--alarm-hold", texts.hold,
                 "With --alarms: time the conditions must stay below a level before it falls [s], 0 to 3600 "
                 "(default 1)")
      ->type_name("S");
  app.add_option("--energy-margin", texts.margin,
                 "With --alarms: IMMINENT when E >= M * E_barrier moving outward, 1 <= M <= 100 (default 1.5)")
      ->type_name("M");
}

void parse_alarm_options(const CLI::App& app, const AlarmOptionTexts& texts, sim::AnalysisOptions& options) {
  if (texts.arith == "double") {
    options.arithmetic = sim::Arithmetic::double_precision;
  } else if (texts.arith == "fixed") {
    options.arithmetic = sim::Arithmetic::fixed_point;
    if (options.model != core::ModelKind::linear) {
      throw UsageError("--arith fixed supports the linear model only (got --model " +
                       std::string(model_name(options.model)) + ")");
    }
  } else {
    throw UsageError("--arith must be fixed or double (got " + quoted(texts.arith) + ")");
  }

  options.evaluate_alarm = texts.alarms;
  for (const char* option : {"--lambda-w", "--alarm-hold", "--energy-margin"}) {
    if (given(app, option) && !texts.alarms) {
      throw UsageError(std::string(option) + " sets the instability alarm: give --alarms too");
    }
  }
  core::AlarmSettings& a = options.alarm;
  if (given(app, "--lambda-w")) {
    a.lambda_warning = parse_finite_number("--lambda-w", texts.lambda_w);
    if (!(a.lambda_warning > 0.0 && a.lambda_warning <= 1.0)) {
      throw UsageError("--lambda-w must be in (0, 1], a fraction of x_inst (got " + number_text(a.lambda_warning) +
                       ")");
    }
  }
  if (given(app, "--alarm-hold")) {
    a.hold_s = parse_finite_number("--alarm-hold", texts.hold);
    if (!(a.hold_s >= 0.0 && a.hold_s <= 3600.0)) {
      throw UsageError("--alarm-hold must be in [0, 3600] s (got " + number_text(a.hold_s) + ")");
    }
  }
  if (given(app, "--energy-margin")) {
    a.energy_margin = parse_finite_number("--energy-margin", texts.margin);
    if (!(a.energy_margin >= 1.0 && a.energy_margin <= 100.0)) {
      throw UsageError("--energy-margin must be in [1, 100], a multiple of the energy barrier (got " +
                       number_text(a.energy_margin) + ")");
    }
  }
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
               {bit::arithmetic_saturated, "arithmetic_saturated"}};
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

}  // namespace rockwatch::cli
