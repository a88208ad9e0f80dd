#include "identify/identify_request.hpp"

#include <string>

#include "common/process/output_file.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

struct RawOptions {
  RecordOptionTexts record;
  WallOptionTexts wall;
  std::string wall_sensors, scale_pga, r = "exp", max_step, plot, wall_out, bootstrap, bootstrap_seed, jobs;
  bool json = false;
};

const char* const kFooter =
    "Identifies the wall from a test (SPEC 9): maximum likelihood (nonlinear least squares) of the displacement\n"
    "transducer's samples against the engine's response over the whole record, Levenberg-Marquardt from the best\n"
    "point of a grid around the starting wall. Without --record/--suite the ground is at rest: a snap-back test\n"
    "released at t = 0 (the release displacement x0 is identified). Identified: the thickness b and a common scale\n"
    "of h1 and h2 (an equivalent wall reproducing the identified x_inst and free-rocking rate), r, the transducer's\n"
    "zero offset (and x0); held at the starting wall's: h1:h2, rho, Fp, a, a', g.\n"
    "\n"
    "Standard errors: by default the curvature of the minimum, s^2 (J'J)^-1. For a snap-back test they are honest;\n"
    "a forced response's cost has many narrow minima, and the curvature says how narrow the one found is, not how\n"
    "far from the wall it may be: give a forced test --bootstrap N (e.g. 20), N refits of the fitted response plus\n"
    "new noise, whose spread is then the standard error (N times the fit's run time, on --jobs threads).\n"
    "\n"
    "Exit status: 0 identified, 2 invalid options or input, or a record that does not identify the wall (no\n"
    "impact, too short, at rest throughout: the message says why), 1 internal error.\n"
    "\n"
    "Examples:\n"
    "  rockwatch simulate --x0 0.05 --b 0.09 --r 0.85 --t-end 8 --sensors-out snap.csv\n"
    "  rockwatch identify --wall-sensors snap.csv --wall-out wall.json --plot fit.png\n"
    "  rockwatch simulate --wall-file wall.json --record RSN6_IMPVALL.I_I-ELC180-hor1.AT2 --scale-pga 0.2\n";

void add_options(CLI::App& app, RawOptions& raw) {
  app.add_option("--wall-sensors", raw.wall_sensors,
                 "The test's wall sensors (CSV t_s,x_mid_m[,a_mid_mps2], as simulate --sensors-out): required")
      ->type_name("FILE.csv");
  add_record_options(app, raw.record, VerticalOptions::allowed);
  app.add_option("--scale-pga", raw.scale_pga, "Scale the record to peak |u''| = G*g, as simulate")->type_name("G");
  add_wall_options(app, raw.wall);
  app.add_option("--r", raw.r, "Start of r: ana | exp (default) | impulse | a value in [0, 1]")->type_name("R");
  add_max_step_option(app, raw.max_step);
  app.add_flag("--json", raw.json, "Print the result as one JSON object on stdout");
  app.add_option("--plot", raw.plot, "Draw the measured and fitted x_mid(t) as PNG")->type_name("FILE.png");
  app.add_option("--wall-out", raw.wall_out,
                 "Write the identified wall (and r) as a wall file for --wall-file of simulate, study, demo, monitor")
      ->type_name("FILE.json");
  app.add_option("--bootstrap", raw.bootstrap,
                 "Standard errors from N parametric bootstrap refits, 0 to 10000 (default 0: the curvature's)")
      ->type_name("N");
  app.add_option("--bootstrap-seed", raw.bootstrap_seed, "Seed of the bootstrap's noise, 0 to 2^64-1 (default 1)")
      ->type_name("S");
  app.add_option("--jobs", raw.jobs, "The bootstrap's threads; 0 = every hardware thread (default 0)")->type_name("N");
  app.footer(kFooter);
}

}  // namespace

IdentifyParse parse_identify_arguments(int argc, const char* const* argv) {
  CLI::App app{"Identify a wall's capacity, stiffness and restitution from a test record (snap-back or forced).",
               "rockwatch identify"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "identify")) {
    return IdentifyParse{std::nullopt, std::move(*help)};
  }
  IdentifyRequest q;
  if (!given(app, "--wall-sensors") || raw.wall_sensors.empty()) {
    throw UsageError("--wall-sensors FILE.csv is required: the test's displacement transducer samples");
  }
  check_input_file("--wall-sensors", raw.wall_sensors, "a wall-sensor CSV file");
  q.wall_sensors_path = raw.wall_sensors;
  const WallChoice wall = parse_wall_options(app, raw.wall);
  q.start_wall = wall.wall;
  q.start_wall_text = wall.wall_file_path ? "wall file " + *wall.wall_file_path : wall.name + " wall";
  for (const std::string& o : wall.options_given) q.start_wall_text += (o == wall.options_given.front() ? " with " : ", ") + o;
  q.start_r = restitution_of(app, wall, raw.r);
  if (given(app, "--record") || given(app, "--suite")) {
    q.record = parse_record_selection(app, raw.record, q.start_wall.g_mps2);
    if (given(app, "--scale-pga")) q.scale_pga_g = parse_positive_number("--scale-pga", raw.scale_pga, " (a multiple of g)");
  } else {
    for (const char* option : {"--vertical", "--vertical-from-suite", "--channel", "--vertical-channel", "--gain",
                               "--units", "--dt", "--component", "--set", "--scale-pga"}) {
      if (given(app, option)) {
        throw UsageError(std::string(option) + " needs a record (--record or --suite); without one the test is a "
                         "snap-back test on ground at rest");
      }
    }
  }
  if (given(app, "--max-step")) q.max_step_s = parse_positive_number("--max-step", raw.max_step, " s");
  q.json = raw.json;
  if (given(app, "--plot")) {
    if (raw.plot.empty()) throw UsageError("--plot needs a file name");
    check_output_file("--plot", raw.plot);
    q.plot_path = raw.plot;
  }
  if (given(app, "--wall-out")) {
    if (raw.wall_out.empty()) throw UsageError("--wall-out needs a file name");
    check_output_file("--wall-out", raw.wall_out);
    q.wall_out_path = raw.wall_out;
  }
  if (given(app, "--bootstrap")) {
    const std::optional<std::uint64_t> n = whole_number(raw.bootstrap, 0, 10000);
    if (!n) throw UsageError("--bootstrap must be a whole number from 0 to 10000 (got " + options::quoted(raw.bootstrap) + ")");
    q.bootstrap = int(*n);
  }
  if (given(app, "--bootstrap-seed")) {
    const std::optional<std::uint64_t> seed = whole_number(raw.bootstrap_seed, 0, UINT64_MAX);
    if (!seed) {
      throw UsageError("--bootstrap-seed must be a whole number from 0 to 2^64-1 (got " +
                       options::quoted(raw.bootstrap_seed) + ")");
    }
    q.bootstrap_seed = *seed;
  }
  if (given(app, "--jobs")) {
    const std::optional<std::uint64_t> jobs = whole_number(raw.jobs, 0, 256);
    if (!jobs) throw UsageError("--jobs must be a whole number from 0 (every hardware thread) to 256 (got " + options::quoted(raw.jobs) + ")");
    q.jobs = std::size_t(*jobs);
  }
  if (q.bootstrap == 0) {
    for (const char* option : {"--bootstrap-seed", "--jobs"}) {
      if (given(app, option)) throw UsageError(std::string(option) + " needs --bootstrap N (N >= 1)");
    }
  }
  return IdentifyParse{q, {}};
}

sim::IdentificationInput identification_input(const IdentifyRequest& q) {
  sim::IdentificationInput in;
  in.start_wall = q.start_wall;
  in.start_r = core::restitution_energy_ratio(q.start_wall, q.start_r);
  in.max_step_s = q.max_step_s;
  in.bootstrap_replicates = q.bootstrap;
  in.bootstrap_seed = q.bootstrap_seed;
  in.bootstrap_jobs = q.jobs;
  return in;
}

}  // namespace rockwatch::cli
