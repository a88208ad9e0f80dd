#include "simulate/simulate_request.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/output_file.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"

namespace rockwatch::cli {

namespace {

// Options are read as text and converted by option_values, so every message has one form and nan/inf are refused
// the same way everywhere.
struct RawOptions {
  RecordOptionTexts record;
  WallOptionTexts wall;
  AlarmOptionTexts alarm;
  std::string scale_pga;
  std::string r = "exp", model = "linear", kappa, max_step, t_end, out;
  bool json = false;
};

const char* const kFooter =
    "Conventions (SPEC sections 1-4): per metre of wall; x is the horizontal displacement of the mid-height hinge;\n"
    "u'' > 0 pushes the wall towards x < 0; v'' is up positive and enters through G = g + v'' (G <= 0 is lift-off,\n"
    "outside the model). Collapse when |x| >= kappa * x_inst; t_exceed is the first time |x| >= x_inst.\n"
    "Times are seconds from the first sample of --record.\n"
    "\n"
    "Exit status: 0 analysis done (whatever the verdict), 2 invalid options or input, 1 internal error.\n"
    "\n"
    "Record selection: --record FILE, or --suite DIR --set N --component X|Y|Z for a record of a suite written by\n"
    "rockwatch generate (--vertical-from-suite adds the set's Z as the vertical, on the same time grid).\n"
    "--component also picks the component of a suite set file given as --record; --channel (--vertical-channel)\n"
    "the channel of a multi-channel miniSEED file, whose counts --gain converts to m/s2.\n"
    "--json prints one object with exactly the documented keys; only with --suite also suite (dir, name, set,\n"
    "component, file, vertical_component), with --component on a --record file component, with --channel\n"
    "channel, with --vertical-channel vertical_channel, with --gain gain_counts_per_mps2, with --arith arithmetic\n"
    "(and saturated for fixed), with --alarms alarm (settings, max_level, first times, transitions).\n"
    "\n"
    "Instability alarm (--alarms), evaluated after every integration step: ROCKING while the wall moves; WARNING\n"
    "at |x| >= lambda_w x_inst; IMMINENT at |x| >= x_inst or when the energy of the linear model reaches\n"
    "M E_barrier while moving outward; COLLAPSED at kappa x_inst (latched). Levels rise at once and fall after the\n"
    "conditions stayed below for the hold time. Each transition lists the time, level, reasons, x and the predicted\n"
    "time to reach x_inst with no further input (linear model; none when the wall would turn back).\n"
    "\n"
    "Examples:\n"
    "  rockwatch simulate --record RSN6_IMPVALL.I_I-ELC180-hor1.AT2 --scale-pga 0.25 --r ana --out history.csv\n"
    "  rockwatch simulate --suite suite --set 3 --component X --vertical-from-suite --scale-pga 0.2 --r ana\n";

void add_options(CLI::App& app, RawOptions& raw) {
  add_record_options(app, raw.record, VerticalOptions::allowed);
  app.add_option("--scale-pga", raw.scale_pga,
                 "Scale the horizontal record to peak |u''| = G*g; the vertical by the same factor")
      ->type_name("G");
  add_wall_options(app, raw.wall);
  add_restitution_option(app, raw.r);
  app.add_option("--model", raw.model, "Equation of motion: linear (default, the paper's) | full")
      ->type_name("linear|full");
  add_kappa_option(app, raw.kappa);
  app.add_option("--max-step", raw.max_step, "Longest integration step; larger record steps are sub-stepped [s] (default 0.005)")
      ->type_name("S");
  app.add_option("--t-end", raw.t_end, "End of the forced phase [s] (default: record duration; zero input after it)")
      ->type_name("S");
  app.add_option("--out", raw.out, "Write the time history (one row per integration step) as CSV")->type_name("FILE.csv");
  add_alarm_options(app, raw.alarm);
  app.add_flag("--json", raw.json, "Print the result as one JSON object on stdout");
  app.footer(kFooter);
}

}  // namespace

SimulateParse parse_simulate_arguments(int argc, const char* const* argv) {
  CLI::App app{"Response of an unreinforced masonry wall rocking out of plane (two-block model, Newmark) to a "
               "ground-motion record.",
               "rockwatch simulate"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "simulate")) {
    return SimulateParse{std::nullopt, std::move(*help)};
  }

  SimulateRequest q;
  WallChoice wall = parse_wall_options(app, raw.wall);
  q.wall = wall.wall;
  q.wall_name = wall.name;
  q.wall_options_given = std::move(wall.options_given);
  q.record = parse_record_selection(app, raw.record, q.wall.g_mps2);
  if (given(app, "--scale-pga")) q.scale_pga_g = parse_positive_number("--scale-pga", raw.scale_pga, " (a multiple of g)");

  q.analysis.restitution = parse_restitution("--r", raw.r);
  q.analysis.model = parse_model("--model", raw.model);
  check_computable(q.wall, q.analysis);
  parse_alarm_options(app, raw.alarm, q.analysis);
  q.arith_given = given(app, "--arith");
  if (q.analysis.evaluate_alarm) q.analysis.max_alarm_transitions_kept = kMaxAlarmTransitionsListed;
  if (given(app, "--kappa")) q.analysis.kappa = parse_kappa("--kappa", raw.kappa);
  if (given(app, "--max-step")) q.analysis.max_step_s = parse_positive_number("--max-step", raw.max_step, " s");
  if (given(app, "--t-end")) {
    const double t_end_s = parse_finite_number("--t-end", raw.t_end);
    if (!(t_end_s >= 0.0)) throw UsageError("--t-end must be >= 0 s (got " + number_text(t_end_s) + ")");
    q.analysis.t_end_s = t_end_s;
  }
  if (given(app, "--out")) {
    if (raw.out.empty()) throw UsageError("--out needs a file name");
    check_output_file("--out", raw.out);
    q.out_csv_path = raw.out;
    q.analysis.keep_history = true;
  }
  q.json = raw.json;
  return SimulateParse{q, {}};
}

}  // namespace rockwatch::cli
