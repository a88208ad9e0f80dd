#include "simulate_request.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "command_line.hpp"
#include "option_values.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "usage_error.hpp"

namespace rockwatch::cli {

namespace {

// Options are read as text and converted by option_values, so every message has one form and nan/inf are refused
// the same way everywhere.
struct RawOptions {
  RecordOptionTexts record;
  std::string scale_pga, wall = "paper";
  std::string b, h1, h2, rho, fp, a, a_prime, g;
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
    "channel, with --vertical-channel vertical_channel, with --gain gain_counts_per_mps2.\n"
    "\n"
    "Examples:\n"
    "  rockwatch simulate --record RSN6_IMPVALL.I_I-ELC180-hor1.AT2 --scale-pga 0.25 --r ana --out history.csv\n"
    "  rockwatch simulate --suite suite --set 3 --component X --vertical-from-suite --scale-pga 0.2 --r ana\n";

void add_options(CLI::App& app, RawOptions& raw) {
  add_record_options(app, raw.record, VerticalOptions::allowed);
  app.add_option("--scale-pga", raw.scale_pga,
                 "Scale the horizontal record to peak |u''| = G*g; the vertical by the same factor")
      ->type_name("G");
  app.add_option("--wall", raw.wall, "Base wall: paper (b 0.10, h1 = h2 = 1.75, rho 1800, Fp 0, a = a' = 0)")
      ->type_name("paper");
  app.add_option("--b", raw.b, "Wall thickness b [m]")->type_name("M");
  app.add_option("--h1", raw.h1, "Bottom block height, ground to mid-height hinge [m]")->type_name("M");
  app.add_option("--h2", raw.h2, "Top block height, mid-height hinge to top restraint [m]")->type_name("M");
  app.add_option("--rho", raw.rho, "Masonry density [kg/m3]")->type_name("KG_M3");
  app.add_option("--fp", raw.fp, "Overburden on the top of the wall [N per m of wall]")->type_name("N_PER_M");
  app.add_option("--a", raw.a, "Overburden eccentricity while x < 0, fraction of b from the top hinge, in [0, 1]")
      ->type_name("A");
  app.add_option("--a-prime", raw.a_prime, "Overburden eccentricity while x > 0, fraction of b, in [0, 1]")
      ->type_name("A");
  app.add_option("--g", raw.g, "Gravity [m/s2] (default 9.81); also converts records in units of g")->type_name("MPS2");
  app.add_option("--r", raw.r, "Energy ratio at impact: ana | exp (default, 0.9 ana) | impulse | a value in [0, 1]")
      ->type_name("R");
  app.add_option("--model", raw.model, "Equation of motion: linear (default, the paper's) | full")
      ->type_name("linear|full");
  app.add_option("--kappa", raw.kappa, "Collapse at |x| >= kappa * x_inst (default 2, >= 1)")->type_name("K");
  app.add_option("--max-step", raw.max_step, "Longest integration step; larger record steps are sub-stepped [s] (default 0.005)")
      ->type_name("S");
  app.add_option("--t-end", raw.t_end, "End of the forced phase [s] (default: record duration; zero input after it)")
      ->type_name("S");
  app.add_option("--out", raw.out, "Write the time history (one row per integration step) as CSV")->type_name("FILE.csv");
  app.add_flag("--json", raw.json, "Print the result as one JSON object on stdout");
  app.footer(kFooter);
}

struct WallField {
  const char* field;   // core::validate_wall's name
  const char* option;  // the option that sets it
  double core::WallParameters::*member;
  std::string RawOptions::*text;
};

constexpr WallField kWallFields[] = {
    {"b", "--b", &core::WallParameters::b_m, &RawOptions::b},
    {"h1", "--h1", &core::WallParameters::h1_m, &RawOptions::h1},
    {"h2", "--h2", &core::WallParameters::h2_m, &RawOptions::h2},
    {"rho", "--rho", &core::WallParameters::rho_kgpm3, &RawOptions::rho},
    {"fp", "--fp", &core::WallParameters::fp_npm, &RawOptions::fp},
    {"a", "--a", &core::WallParameters::a, &RawOptions::a},
    {"a_prime", "--a-prime", &core::WallParameters::a_prime, &RawOptions::a_prime},
    {"g", "--g", &core::WallParameters::g_mps2, &RawOptions::g},
};

// Names the option at fault, and says when its value was the base wall's rather than the user's.
[[noreturn]] void report_invalid_wall(const CLI::App& app, const core::WallParameters& wall,
                                      const core::WallCheck& check) {
  for (const WallField& f : kWallFields) {
    if (std::string(check.field) != f.field) continue;
    std::string message = std::string(f.option) + " " + check.message + " (got " + number_text(wall.*f.member);
    if (!given(app, f.option)) message += ", the paper wall's value";
    const bool compares_with_b =
        check.code == core::WallError::h1_not_above_b || check.code == core::WallError::h2_not_above_b;
    if (compares_with_b && given(app, "--b")) message += "; --b " + number_text(wall.b_m);
    throw UsageError(message + ")");
  }
  throw UsageError(std::string("wall parameter ") + check.field + " " + check.message);
}

// The wall: the base wall with the given fields replaced, validated by core so the CLI and the engine agree on
// what a valid wall is.
core::WallParameters build_wall(const CLI::App& app, const RawOptions& raw, std::vector<std::string>& given_options) {
  if (raw.wall != "paper") {
    throw UsageError("--wall must be paper, the only built-in wall (got " + quoted(raw.wall) +
                     "); set its dimensions with --b, --h1, --h2, --rho, --fp, --a, --a-prime");
  }
  core::WallParameters wall = core::paper_wall();
  for (const WallField& f : kWallFields) {
    if (!given(app, f.option)) continue;
    wall.*f.member = parse_finite_number(f.option, raw.*f.text);
    given_options.emplace_back(f.option);
  }
  const core::WallCheck check = core::validate_wall(wall);
  if (check.ok()) return wall;
  report_invalid_wall(app, wall, check);
}

// validate_wall accepts every finite positive size, but extremes (--rho 1e308, --h1 1e300) overflow the model's
// constants into inf/NaN, which would come out as null results rather than an error.
void check_computable(const core::WallParameters& wall, const sim::AnalysisOptions& options) {
  const core::ModelConstants<double> c = core::model_constants(wall, options.model);
  const double r = core::restitution_energy_ratio(wall, options.restitution);
  for (const core::Side side : {core::Side::negative, core::Side::positive}) {
    const double x_inst_m = core::x_inst_m(c, side, wall.g_mps2);
    const double threshold_mps2 = core::threshold_mps2(c, side, wall.g_mps2);
    const bool ok = std::isfinite(x_inst_m) && x_inst_m > 0.0 && std::isfinite(threshold_mps2) &&
                    threshold_mps2 > 0.0 && std::isfinite(r) && r >= 0.0 && r <= 1.0;
    if (!ok) {
      throw UsageError("the wall options give values the model cannot compute (x_inst = " + number_text(x_inst_m) +
                       " m, threshold = " + number_text(threshold_mps2) + " m/s2, r = " + number_text(r) +
                       "): check --b, --h1, --h2, --rho, --fp and --g for extreme values");
    }
  }
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
  q.wall = build_wall(app, raw, q.wall_options_given);
  q.wall_name = raw.wall;
  q.record = parse_record_selection(app, raw.record, q.wall.g_mps2);
  if (given(app, "--scale-pga")) q.scale_pga_g = parse_positive_number("--scale-pga", raw.scale_pga, " (a multiple of g)");

  q.analysis.restitution = parse_restitution("--r", raw.r);
  q.analysis.model = parse_model("--model", raw.model);
  check_computable(q.wall, q.analysis);
  if (given(app, "--kappa")) {
    q.analysis.kappa = parse_finite_number("--kappa", raw.kappa);
    if (!(q.analysis.kappa >= 1.0)) {
      throw UsageError("--kappa must be >= 1: collapse cannot come before x_inst (got " + number_text(q.analysis.kappa) +
                       ")");
    }
  }
  if (given(app, "--max-step")) q.analysis.max_step_s = parse_positive_number("--max-step", raw.max_step, " s");
  if (given(app, "--t-end")) {
    const double t_end_s = parse_finite_number("--t-end", raw.t_end);
    if (!(t_end_s >= 0.0)) throw UsageError("--t-end must be >= 0 s (got " + number_text(t_end_s) + ")");
    q.analysis.t_end_s = t_end_s;
  }
  if (given(app, "--out")) {
    if (raw.out.empty()) throw UsageError("--out needs a file name");
    q.out_csv_path = raw.out;
    q.analysis.keep_history = true;
  }
  q.json = raw.json;
  return SimulateParse{q, {}};
}

}  // namespace rockwatch::cli
