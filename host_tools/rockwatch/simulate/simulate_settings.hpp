// What `rockwatch simulate` computes with, as typed values, and the one function that checks them and builds the
// request from them: the command line's parser (simulate_request.cpp) converts its texts into SimulateSettings, the
// Python module (host_tools/python) fills them from its keywords; both call apply_simulate_settings, so the checks
// and the messages (naming the option, e.g. "--max-step must be > 0 s (got 0)") are the same. The size of the work a
// run may ask for is checked once, here too (check_work_size), when the input motion is known.
#pragma once

#include <optional>
#include <string>
#include <variant>

#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "simulate/simulate_request.hpp"

namespace rockwatch::cli {

struct SimulateSettings {
  options::WallChoice wall;                              // the base wall and its fields (--wall-file, --b, ...)
  // --r: ana | exp | impulse | an energy ratio in [0, 1] (a name, or a number's text, or a number); none: the wall
  // file's r, else exp.
  std::optional<std::variant<std::string, double>> r;
  std::string model = "linear";                          // --model: linear | full
  std::optional<double> scale_pga_g;                     // --scale-pga [g]
  std::optional<double> kappa;                           // --kappa
  std::optional<double> max_step_s;                      // --max-step [s]
  std::optional<double> t_end_s;                         // --t-end [s]
  options::AlarmOptionValues alarm;                      // --arith, --alarms, --lambda-w, ...
  bool arith_given = false;                              // --arith given: the JSON says which arithmetic ran
  bool keep_history = false;                             // every integration step kept (--out, history=True)
  // How the messages of check_work_size name what keeps the history ("with --out"; the module's "keeping the
  // history (history=True)").
  std::string history_kept_by = "with --out";
};

// Checks the settings and sets the request's wall, scale_pga_g, analysis (restitution, model, alarm, kappa, max step,
// t_end, history) and arith_given. Throws UsageError naming the option at fault.
void apply_simulate_settings(const SimulateSettings& settings, SimulateRequest& q);

// Bounds on the work one run may ask for, given the input's sample interval and duration: a typo such as
// --max-step 1e-9 or --t-end 1e9 is an error message, not hours of computing or an exhausted machine.
void check_work_size(const SimulateRequest& q, const sim::GroundMotion& motion);

}  // namespace rockwatch::cli
