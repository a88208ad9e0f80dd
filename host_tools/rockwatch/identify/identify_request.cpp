#include "identify/identify_request.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "common/process/output_file.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace identify_request {

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

}  // namespace identify_request
}  // namespace

namespace {
namespace identify_request {

// The whole numbers' ranges and messages, one place for the command line's texts and the module's integers.
struct WholeOption {
  const char* option;
  std::uint64_t max;
  const char* expected;
};
constexpr WholeOption kBootstrap{"--bootstrap", 10000, "a whole number from 0 to 10000"};
constexpr WholeOption kBootstrapSeed{"--bootstrap-seed", UINT64_MAX, "a whole number from 0 to 2^64-1"};
constexpr WholeOption kJobs{"--jobs", 256, "a whole number from 0 (every hardware thread) to 256"};

[[noreturn]] void refuse_whole(const WholeOption& o, const std::string& text) {
  throw UsageError(std::string(o.option) + " must be " + o.expected + " (got " + options::quoted(text) + ")");
}

std::uint64_t parse_whole(const WholeOption& o, const std::string& text) {
  const std::optional<std::uint64_t> n = whole_number(text, 0, o.max);
  if (!n) refuse_whole(o, text);
  return *n;
}

std::uint64_t check_whole(const WholeOption& o, long long value) {
  if (value < 0 || static_cast<std::uint64_t>(value) > o.max) refuse_whole(o, std::to_string(value));
  return static_cast<std::uint64_t>(value);
}

// The record options a snap-back test (no record) cannot take, in the order they are reported.
const char* record_option_without_record(const IdentifySettings& s) {
  const RecordSelectionSettings& r = s.record;
  const std::pair<const char*, bool> options[] = {
      {"--vertical", bool(r.vertical)},   {"--vertical-from-suite", r.vertical_from_suite},
      {"--channel", bool(r.channel)},     {"--vertical-channel", bool(r.vertical_channel)},
      {"--gain", bool(r.gain_counts_per_mps2)}, {"--units", bool(r.units)},
      {"--dt", bool(r.dt_s)},             {"--component", bool(r.component)},
      {"--set", bool(r.set)},             {"--scale-pga", bool(s.scale_pga_g)}};
  for (const auto& [option, given_option] : options) {
    if (given_option) return option;
  }
  return nullptr;
}

std::string output_path(const char* option, const std::string& path) {
  if (path.empty()) throw UsageError(std::string(option) + " needs a file name");
  check_output_file(option, path);
  return path;
}

}  // namespace identify_request
}  // namespace

IdentifyRequest build_identify_request(const IdentifySettings& s) {
  using namespace identify_request;
  IdentifyRequest q;
  if (!s.wall_sensors || s.wall_sensors->empty()) {
    throw UsageError("--wall-sensors FILE.csv is required: the test's displacement transducer samples");
  }
  check_input_file("--wall-sensors", *s.wall_sensors, "a wall-sensor CSV file");
  q.wall_sensors_path = *s.wall_sensors;
  const WallChoice& wall = s.wall;
  q.start_wall = wall.wall;
  q.start_wall_text = wall.wall_file_path ? "wall file " + *wall.wall_file_path : wall.name + " wall";
  for (const std::string& o : wall.options_given) q.start_wall_text += (o == wall.options_given.front() ? " with " : ", ") + o;
  q.start_r = restitution_of(s.r, wall, "exp");
  if (s.record.record || s.record.suite) {
    q.record = check_record_selection(s.record, q.start_wall.g_mps2);
    if (s.scale_pga_g) q.scale_pga_g = check_positive_number("--scale-pga", *s.scale_pga_g, " (a multiple of g)");
  } else if (const char* option = record_option_without_record(s)) {
    throw UsageError(std::string(option) + " needs a record (--record or --suite); without one the test is a "
                     "snap-back test on ground at rest");
  }
  if (s.max_step_s) q.max_step_s = check_positive_number("--max-step", *s.max_step_s, " s");
  q.json = s.json;
  if (s.plot) q.plot_path = output_path("--plot", *s.plot);
  if (s.wall_out) q.wall_out_path = output_path("--wall-out", *s.wall_out);
  if (s.bootstrap) q.bootstrap = int(check_whole(kBootstrap, *s.bootstrap));
  if (s.bootstrap_seed) q.bootstrap_seed = *s.bootstrap_seed;
  if (s.jobs) q.jobs = std::size_t(check_whole(kJobs, *s.jobs));
  if (q.bootstrap == 0) {
    if (s.bootstrap_seed) throw UsageError("--bootstrap-seed needs --bootstrap N (N >= 1)");
    if (s.jobs) throw UsageError("--jobs needs --bootstrap N (N >= 1)");
  }
  return q;
}

IdentifyParse parse_identify_arguments(int argc, const char* const* argv) {
  using namespace identify_request;
  CLI::App app{"Identify a wall's capacity, stiffness and restitution from a test record (snap-back or forced).",
               "rockwatch identify"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "identify")) {
    return IdentifyParse{std::nullopt, std::move(*help)};
  }
  IdentifySettings s;
  if (given(app, "--wall-sensors")) s.wall_sensors = raw.wall_sensors;
  // The missing --wall-sensors is the first thing said, before the wall and the record are read.
  if (!s.wall_sensors || s.wall_sensors->empty()) return IdentifyParse{build_identify_request(s), {}};
  s.wall = parse_wall_options(app, raw.wall);
  if (given(app, "--r")) s.r = raw.r;
  s.record = record_selection_settings(app, raw.record);
  if (given(app, "--scale-pga")) s.scale_pga_g = parse_finite_number("--scale-pga", raw.scale_pga);
  if (given(app, "--max-step")) s.max_step_s = parse_finite_number("--max-step", raw.max_step);
  s.json = raw.json;
  if (given(app, "--plot")) s.plot = raw.plot;
  if (given(app, "--wall-out")) s.wall_out = raw.wall_out;
  if (given(app, "--bootstrap")) s.bootstrap = static_cast<long long>(parse_whole(kBootstrap, raw.bootstrap));
  if (given(app, "--bootstrap-seed")) s.bootstrap_seed = parse_whole(kBootstrapSeed, raw.bootstrap_seed);
  if (given(app, "--jobs")) s.jobs = static_cast<long long>(parse_whole(kJobs, raw.jobs));
  return IdentifyParse{build_identify_request(s), {}};
}

sim::IdentificationInput identification_input(const IdentifyRequest& q) {
  using namespace identify_request;
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
