// The engine options of issue 6 shared by simulate and study: --arith fixed|double (the engine's arithmetic) and the
// instability alarm, --alarms with --lambda-w, --alarm-hold and --energy-margin (core::AlarmSettings), validated with
// messages that name the option at fault.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::cli {

struct AlarmOptionTexts {
  std::string arith = "double";
  bool alarms = false;
  std::string lambda_w, hold, margin;
};

// Registers --arith, --alarms, --lambda-w, --alarm-hold and --energy-margin, in that order.
void add_alarm_options(CLI::App& app, AlarmOptionTexts& texts);

// Sets options.arithmetic, evaluate_alarm and alarm. The alarm settings without --alarms, --arith fixed with a model
// other than linear (set options.model first) and values out of range throw UsageError naming the option.
void parse_alarm_options(const CLI::App& app, const AlarmOptionTexts& texts, sim::AnalysisOptions& options);

// "double" | "fixed".
const char* arithmetic_name(sim::Arithmetic arithmetic);

// The alarm_reason bits by name, in bit order ("moving", "energy_over_barrier_outward", ...; "bitN" for a bit this
// tool does not know), and the same joined with ", " ("none" for 0).
std::vector<std::string> alarm_reason_list(std::uint32_t reasons);
std::string alarm_reason_names(std::uint32_t reasons);

}  // namespace rockwatch::cli
