#include "simulate/simulate_request.hpp"

#include <cstdint>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/process/output_file.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/observer_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/sensor_model_options.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "common/process/options_namespace.hpp"
#include "simulate/simulate_settings.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace simulate_request {

// Options are read as text and converted by option_values, so every message has one form and nan/inf are refused
// the same way everywhere.
struct RawOptions {
  RecordOptionTexts record;
  WallOptionTexts wall;
  AlarmOptionTexts alarm;
  std::string scale_pga;
  ObserverOptionTexts observer;
  std::string r = "exp", model = "linear", kappa, max_step, t_end, out, engine_input_out, x0;
  std::string wall_sensors, sensors_out, observer_out;
  SensorModelOptionTexts sensor_model;
  std::string forecast_members, forecast_horizon, forecast_every, forecast_seed, forecast_calibration;
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
    "(and saturated for fixed), with --alarms alarm (settings, max_level, first times, transitions), with\n"
    "--wall-sensors observer (r_estimate, sigma_r, bias_estimate_m, n_updates, n_rejected, x_rms_innovation_m, ...).\n"
    "\n"
    "Ensemble forecast (--forecast-members N --forecast-horizon-s H, SPEC section 10): every --forecast-every-s S\n"
    "seconds while the wall is not at rest, N futures of the wall from its state then, the ground still to come\n"
    "drawn from filtered noise fitted to the last 4 s of the record: P(collapse within H), its Monte-Carlo standard\n"
    "error and quantiles of max |x|/x_inst. --json adds forecast (members, horizon_s, every_s, step_s, seed,\n"
    "at_rest_skipped, series [t_s, p_collapse, p_collapse_se, q50_max_x_over_x_inst, q90_max_x_over_x_inst, and\n"
    "with --alarms alarm: the alarm's level at t_s; p_collapse_calibrated, the recalibrated P of SPEC section 10,\n"
    "with its features energy_ratio_max_2s and x_over_x_inst], calibration [coefficients, horizon_s, applied]).\n"
    "With --wall-sensors the members start from the fused state with the observer's sigma_x, sigma_xd (rho 0),\n"
    "r and capacity at that time, as rockwatch-monitor --forecast does; each entry then also carries them:\n"
    "sigma_x_m, sigma_xd_mps, r_estimate, capacity_scale, stiffness_scale (kappa_c, kappa_k: c, k over the nominal's).\n"
    "\n"
    "--engine-input-out FILE writes the wall engine's configuration (wall, r, kappa, model, step, alarm settings\n"
    "and, with --wall-sensors, the observer's) and the input of every sample as run (the record's samples, then the\n"
    "zeros of the free motion after it, up to where the analysis stopped) with the wall-sensor samples, for\n"
    "scripts/m4-replay.sh, which replays them on an emulated Cortex-M4 (firmware/README.md).\n"
    "\n"
    "Wall sensors (--wall-sensors FILE.csv): a header line naming t_s and x_mid_m and/or a_mid_mps2, then one sample per\n"
    "row (t_s on the record's clock, 0 at its first sample; any rate; an empty field = absent). The wall observer\n"
    "(an extended Kalman filter on x, x', sqrt(r) and the transducer's zero offset) corrects the simulated state after\n"
    "every integration step with the samples whose time has come; the result, --out and the alarm are the fused\n"
    "state's. --sensors-out FILE.csv writes such a file from the wall simulated here (the truth for testing): the\n"
    "displacement x + bias + Gaussian noise (rounded to --sensor-quantum-m), with --sensor-accel-noise-mps2 also\n"
    "a_mid = u'' + x'' - G x / h1 + noise, at --sensor-rate-hz (default the record's rate, linear between steps),\n"
    "without rows inside each --sensor-dropout T0:T1 window.\n"
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
  add_model_option(app, raw.model);
  add_kappa_option(app, raw.kappa);
  add_max_step_option(app, raw.max_step);
  app.add_option("--t-end", raw.t_end, "End of the forced phase [s] (default: record duration; zero input after it)")
      ->type_name("S");
  app.add_option("--x0", raw.x0,
                 "Release test (snap-back): the wall starts at x = X0 with no velocity and is followed until it rests; "
                 "without --record/--suite the ground is at rest (sampled every --dt, default 0.005 s)")
      ->type_name("M");
  app.add_option("--out", raw.out, "Write the time history (one row per integration step) as CSV")->type_name("FILE.csv");
  add_alarm_options(app, raw.alarm);
  app.add_option("--wall-sensors", raw.wall_sensors,
                 "Fuse the wall's sensor samples (CSV: t_s,x_mid_m[,a_mid_mps2]) with the model: the wall observer")
      ->type_name("FILE.csv");
  add_observer_options(app, raw.observer, "With --wall-sensors: ");
  app.add_option("--observer-out", raw.observer_out,
                 "With --wall-sensors: write the observer's estimates at the end of every input sample as CSV (the "
                 "fused x, its sigma, r, the capacity kappa_c, kappa_k, x_inst with their sigma, the observer's flag "
                 "bits and names; SPEC section 11)")
      ->type_name("FILE.csv");
  app.add_option("--sensors-out", raw.sensors_out,
                 "Write sensor samples of the simulated wall (CSV for --wall-sensors): the truth for testing")
      ->type_name("FILE.csv");
  add_sensor_model_options(app, raw.sensor_model, "With --sensors-out: ");
  app.add_option("--engine-input-out", raw.engine_input_out,
                 "Write the engine's configuration and its input of every step (binary) for the Cortex-M4 replay "
                 "(scripts/m4-replay.sh)")
      ->type_name("FILE");
  app.add_option("--forecast-members", raw.forecast_members,
                 "Ensemble forecast of collapse (SPEC section 10): N members per forecast, 1 to 100000 (needs "
                 "--forecast-horizon-s)")
      ->type_name("N");
  app.add_option("--forecast-horizon-s", raw.forecast_horizon,
                 "Ensemble forecast: P(collapse) within H seconds, H in (0, 60]")
      ->type_name("H");
  app.add_option("--forecast-every-s", raw.forecast_every,
                 "Ensemble forecast: one every S seconds while the wall is not at rest, S in [0.01, 60] (default 0.1)")
      ->type_name("S");
  app.add_option("--forecast-calibration", raw.forecast_calibration,
                 "Ensemble forecast: the recalibration's coefficients c0,c1,c2,c3[,c4] (SPEC section 10 "
                 "'Calibrated P'; four numbers: c4 = 0; default: the shipped ones, fitted at H = 3 s and 5 s and "
                 "applied only at those horizons)")
      ->type_name("C0,C1,C2,C3[,C4]");
  app.add_option("--forecast-seed", raw.forecast_seed,
                 "Ensemble forecast: seed of the members, 0 to 2^64-1 (default 29)")
      ->type_name("K");
  app.add_flag("--json", raw.json, "Print the result as one JSON object on stdout");
  app.footer(kFooter);
}

void parse_sensor_options(const CLI::App& app, const RawOptions& raw, SimulateRequest& q) {
  if (given(app, "--wall-sensors")) {
    if (raw.wall_sensors.empty()) throw UsageError("--wall-sensors needs a file name");
    check_input_file("--wall-sensors", raw.wall_sensors, "a wall-sensor CSV file");
    q.wall_sensors_path = raw.wall_sensors;
    q.analysis.observer = parse_observer_options(app, raw.observer);
    if (given(app, "--observer-out")) {
      if (raw.observer_out.empty()) throw UsageError("--observer-out needs a file name");
      check_output_file("--observer-out", raw.observer_out);
      q.observer_out_path = raw.observer_out;
      q.analysis.keep_history = true;  // the estimates are kept with the history
    }
  } else if (given(app, "--observer-out")) {
    throw UsageError("--observer-out writes the wall observer's estimates: give --wall-sensors too");
  } else if (observer_option_given(app)) {
    for (const char* name : kObserverOptionNames) {
      if (given(app, name)) throw UsageError(std::string(name) + " sets the wall observer: give --wall-sensors too");
    }
  }
  if (!given(app, "--sensors-out")) {
    if (const char* name = first_sensor_model_option_given(app)) {
      throw UsageError(std::string(name) + " sets the sensors written by --sensors-out: give it too");
    }
    return;
  }
  if (raw.sensors_out.empty()) throw UsageError("--sensors-out needs a file name");
  if (q.wall_sensors_path) {
    throw UsageError("--sensors-out writes the sensors of the simulated (true) wall, which --wall-sensors would change: "
                     "run them separately");
  }
  check_output_file("--sensors-out", raw.sensors_out);
  q.sensors_out_path = raw.sensors_out;
  q.sensor_model = parse_sensor_model_options(app, raw.sensor_model);
  q.analysis.keep_history = true;  // the samples are taken from the history
}

void parse_forecast_options(const CLI::App& app, const RawOptions& raw, SimulateRequest& q) {
  const bool members = given(app, "--forecast-members"), horizon = given(app, "--forecast-horizon-s");
  if (!members && !horizon) {
    for (const char* name : {"--forecast-every-s", "--forecast-seed", "--forecast-calibration"}) {
      if (given(app, name)) {
        throw UsageError(std::string(name) + " sets the ensemble forecast: give --forecast-members and "
                         "--forecast-horizon-s too");
      }
    }
    return;
  }
  if (!members) throw UsageError("--forecast-horizon-s needs --forecast-members N too");
  if (!horizon) throw UsageError("--forecast-members needs --forecast-horizon-s H too");
  sim::ForecastSettings f;
  const std::optional<std::uint64_t> n =
      whole_number(raw.forecast_members, sim::kForecastMembersMin, sim::kForecastMembersMax);
  if (!n) {
    throw UsageError("--forecast-members must be a whole number from " + std::to_string(sim::kForecastMembersMin) +
                     " to " + std::to_string(sim::kForecastMembersMax) + " (got " + quoted(raw.forecast_members) +
                     ")");
  }
  f.members = static_cast<int>(*n);
  f.horizon_s = parse_finite_number("--forecast-horizon-s", raw.forecast_horizon);
  if (!(f.horizon_s > 0.0 && f.horizon_s <= sim::kForecastHorizonMax_s)) {
    throw UsageError("--forecast-horizon-s must be in (0, " + number_text(sim::kForecastHorizonMax_s) +
                     "] s (got " + number_text(f.horizon_s) + ")");
  }
  if (given(app, "--forecast-every-s")) {
    q.forecast_every_s = parse_number_in("--forecast-every-s", raw.forecast_every, 0.01, 60.0, " s");
  }
  if (given(app, "--forecast-seed")) {
    const std::optional<std::uint64_t> seed = whole_number(raw.forecast_seed, 0, UINT64_MAX);
    if (!seed) {
      throw UsageError("--forecast-seed must be a whole number from 0 to 2^64-1 (got " + quoted(raw.forecast_seed) +
                       ")");
    }
    f.seed = *seed;
  }
  if (given(app, "--forecast-calibration")) {
    std::string why;
    q.forecast_calibration = sim::parse_forecast_calibration(raw.forecast_calibration, f.horizon_s, &why);
    if (!q.forecast_calibration) {
      throw UsageError("--forecast-calibration takes " + why + " (got " + quoted(raw.forecast_calibration) + ")");
    }
  }
  q.forecast = f;
  q.analysis.keep_history = true;  // the forecasts start from the history's states
}

}  // namespace simulate_request
}  // namespace

SimulateParse parse_simulate_arguments(int argc, const char* const* argv) {
  using namespace simulate_request;
  CLI::App app{"Response of an unreinforced masonry wall rocking out of plane (two-block model, Newmark) to a "
               "ground-motion record.",
               "rockwatch simulate"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "simulate")) {
    return SimulateParse{std::nullopt, std::move(*help)};
  }

  SimulateRequest q;
  SimulateSettings settings;
  settings.wall = parse_wall_options(app, raw.wall);
  if (given(app, "--x0")) {
    const double x0_m = parse_finite_number("--x0", raw.x0);
    if (!(std::fabs(x0_m) <= 1.0)) throw UsageError("--x0 must be a displacement in [-1, 1] m (got " + number_text(x0_m) + ")");
    q.analysis.initial_x_m = x0_m;
  }
  if (q.analysis.initial_x_m && !given(app, "--record") && !given(app, "--suite")) {
    // A snap-back test: no record, the ground at rest.
    for (const char* option : {"--vertical", "--vertical-from-suite", "--channel", "--vertical-channel", "--gain",
                               "--units", "--component", "--set", "--scale-pga"}) {
      if (given(app, option)) throw UsageError(std::string(option) + " needs a record (--record or --suite); --x0 alone is a release test on ground at rest");
    }
    q.ground_at_rest = true;
    if (given(app, "--dt")) {
      q.ground_at_rest_dt_s = parse_positive_number("--dt", raw.record.dt, " s");
      if (!(q.ground_at_rest_dt_s <= 1.0)) throw UsageError("--dt must be at most 1 s (got " + number_text(q.ground_at_rest_dt_s) + ")");
    }
  } else {
    q.record = parse_record_selection(app, raw.record, settings.wall.wall.g_mps2);
  }
  if (given(app, "--scale-pga")) settings.scale_pga_g = parse_finite_number("--scale-pga", raw.scale_pga);
  if (given(app, "--r")) settings.r = raw.r;
  settings.model = raw.model;
  settings.alarm = alarm_option_values(app, raw.alarm);
  settings.arith_given = given(app, "--arith");
  if (given(app, "--kappa")) settings.kappa = parse_finite_number("--kappa", raw.kappa);
  if (given(app, "--max-step")) settings.max_step_s = parse_finite_number("--max-step", raw.max_step);
  if (given(app, "--t-end")) settings.t_end_s = parse_finite_number("--t-end", raw.t_end);
  apply_simulate_settings(settings, q);
  if (given(app, "--out")) {
    if (raw.out.empty()) throw UsageError("--out needs a file name");
    check_output_file("--out", raw.out);
    q.out_csv_path = raw.out;
    q.analysis.keep_history = true;
  }
  parse_sensor_options(app, raw, q);
  parse_forecast_options(app, raw, q);
  if (given(app, "--engine-input-out")) {
    if (raw.engine_input_out.empty()) throw UsageError("--engine-input-out needs a file name");
    check_output_file("--engine-input-out", raw.engine_input_out);
    q.engine_input_out_path = raw.engine_input_out;
  }
  q.json = raw.json;
  return SimulateParse{q, {}};
}

}  // namespace rockwatch::cli
