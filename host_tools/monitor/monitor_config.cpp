#include "monitor_config.hpp"

#include "rockwatch/sim/forecast_calibration.hpp"

static_assert(rockwatch::sim::kCalibrationFeatures == 5, "MonitorConfig::forecast calibration holds c0..c4");

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/core/model.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/realtime_options.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_file.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "monitor_command_line.hpp"
#include "monitor_config_file.hpp"
#include "monitor_walls.hpp"

#ifndef ROCKWATCH_VERSION
#define ROCKWATCH_VERSION "unknown"
#endif

namespace rockwatch::monitor {

using options::number_text;
using options::UsageError;
using nlohmann::json;
using namespace config_detail;

namespace {

// ---------------------------------------------------------------------------------------------------------------
// Merging and validation

// A value and where it came from ("--kappa", "--config FILE: kappa", or "" for the default).
template <typename T>
struct Sourced {
  T value;
  std::string origin;
};

template <typename T>
Sourced<T> pick(const T& fallback, const std::optional<T>& from_file, const std::string& file_label) {
  if (from_file) return {*from_file, file_label};
  return {fallback, ""};
}

std::string name_of(const std::string& origin, const char* default_name) {
  return origin.empty() ? std::string(default_name) + " (default)" : origin;
}

void check_range(bool ok, const std::string& name, const std::string& expected, double got) {
  if (!ok) throw UsageError(name + " must be " + expected + " (got " + number_text(got) + ")");
}

// The wall: the command line's when the file has none (exactly `rockwatch simulate`'s parsing and messages);
// otherwise the file's fields with the options given on the command line replacing them.
core::WallParameters merge_wall(const CLI::App& app, const RawOptions& raw, const FileValues& file,
                                const ConfigReader* reader, std::string& origin,
                                const std::optional<options::WallFile>& wall_file) {
  bool file_wall = false;
  for (const auto& f : file.wall) file_wall = file_wall || f.has_value();
  const bool config_wall_file = file.wall_file && !options::given(app, "--wall-file");
  if ((!file_wall && !config_wall_file) || options::given(app, "--wall")) {
    const options::WallChoice choice = options::parse_wall_options(app, raw.wall);
    const std::string base = choice.wall_file_path ? "wall file " + *choice.wall_file_path : "paper wall";
    origin = choice.options_given.empty() ? base : base + " with " + join(choice.options_given, ", ");
    return choice.wall;
  }
  core::WallParameters wall = wall_file ? wall_file->wall : core::paper_wall();
  const std::string base_value = wall_file ? " (the wall file's value)" : " (the paper wall's value)";
  std::string sources[8];
  std::vector<std::string> given_names;
  for (int i = 0; i < 8; ++i) {
    const WallField& f = kWallFields[i];
    if (options::given(app, f.option)) {
      wall.*f.member = options::parse_finite_number(f.option, raw.wall.*f.text);
      sources[i] = f.option;
      given_names.emplace_back(f.option);
    } else if (file.wall[i]) {
      wall.*f.member = *file.wall[i];
      sources[i] = reader->key_label(std::string("wall.") + f.key);
      given_names.push_back(std::string("wall.") + f.key);
    } else {
      sources[i] = std::string(f.option) + base_value;
    }
  }
  origin = (wall_file ? std::string("wall file") : std::string("paper wall")) +
           (given_names.empty() ? std::string() : " with " + join(given_names, ", "));
  const core::WallCheck check = core::validate_wall(wall);
  if (check.ok()) return wall;
  for (int i = 0; i < 8; ++i) {
    const WallField& f = kWallFields[i];
    if (std::string(check.field) != f.key) continue;
    std::string message = sources[i] + " " + check.message + " (got " + number_text(wall.*f.member);
    if (check.code == core::WallError::h1_not_above_b || check.code == core::WallError::h2_not_above_b) {
      message += "; b = " + number_text(wall.b_m) + " from " + sources[0];
    }
    throw UsageError(message + ")");
  }
  throw UsageError(std::string("wall parameter ") + check.field + " " + check.message);
}

void check_wall_computable(const core::WallParameters& wall, const core::Restitution& r, core::ModelKind model,
                           const std::string& origin) {
  sim::AnalysisOptions options;
  options.restitution = r;
  options.model = model;
  try {
    options::check_computable(wall, options);
  } catch (const UsageError& e) {
    throw UsageError(std::string(e.what()) + " (wall: " + origin + ")");
  }
}

bool channel_text_ok(const std::string& name) {
  if (name.empty() || name.size() >= firmware::kChannelNameMax) return false;
  for (const char c : name) {
    if (c <= ' ' || c > '~') return false;  // printable ASCII, no spaces
  }
  return true;
}

// The live forecast (monitor_forecast.hpp): the file's forecast object, --forecast N,H and --forecast-rate over it.
void merge_forecast(const CLI::App& app, const RawOptions& raw, const FileValues& file, const std::string& label,
                    MonitorConfig& config) {
  ForecastConfig& f = config.forecast;
  const bool cli = options::given(app, "--forecast");
  f.enabled = cli || file.forecast_enabled.value_or(false);
  f.origin = cli ? "--forecast" : label;
  if (!f.enabled) {
    for (const char* name : {"--forecast-rate", "--forecast-calibration"}) {
      if (options::given(app, name)) {
        throw UsageError(std::string(name) + " sets the live forecast: give --forecast N,H too (or forecast.enabled)");
      }
    }
    return;
  }
  if (file.forecast_calibration) f.calibration = *file.forecast_calibration;
  if (options::given(app, "--forecast-calibration")) {
    std::string why;
    const auto cal = sim::parse_forecast_calibration(raw.forecast_calibration, 0.0, &why);
    if (!cal) {
      throw UsageError("--forecast-calibration takes " + why + " (got " + options::quoted(raw.forecast_calibration) +
                       ")");
    }
    f.calibration = cal->c;
  }
  if (file.forecast_members) f.members = *file.forecast_members;
  if (file.forecast_horizon_s) f.horizon_s = *file.forecast_horizon_s;
  if (file.forecast_rate_hz) f.rate_hz = *file.forecast_rate_hz;
  if (file.forecast_seed) f.seed = *file.forecast_seed;
  if (file.forecast_channel) {
    if (!channel_text_ok(*file.forecast_channel)) {
      throw UsageError(label + ".channel must be 1 to " + std::to_string(firmware::kChannelNameMax - 1) +
                       " printable ASCII characters without spaces (got " + options::quoted(*file.forecast_channel) +
                       ")");
    }
    f.channel = *file.forecast_channel;
  }
  if (cli) {
    const std::vector<std::string> parts = options::split_fields(raw.forecast, ',');
    const std::string expected = "--forecast expects N,H: N members in [1, 100000] and a horizon H in (0, 60] s, e.g. "
                                 "200,5 (got " + options::quoted(raw.forecast) + ")";
    if (parts.size() != 2) throw UsageError(expected);
    const std::optional<std::uint64_t> n = options::whole_number(parts[0], 1, 100000);
    if (!n) throw UsageError("--forecast: N must be a whole number of members in [1, 100000] (got " +
                             options::quoted(raw.forecast) + ")");
    double h = 0.0;
    try {
      h = options::parse_finite_number("--forecast", parts[1]);
    } catch (const UsageError&) {
      throw UsageError(expected);
    }
    if (!(h > 0.0 && h <= 60.0)) {
      throw UsageError("--forecast: the horizon H must be in (0, 60] s (got " + options::quoted(raw.forecast) + ")");
    }
    f.members = static_cast<int>(*n);
    f.horizon_s = h;
  }
  if (options::given(app, "--forecast-rate")) {
    const double r = options::parse_finite_number("--forecast-rate", raw.forecast_rate);
    if (!(r >= kForecastRateMin_hz && r <= kForecastRateMax_hz)) {
      throw UsageError("--forecast-rate must be in [0.1, 100] forecasts per second (got " +
                       options::quoted(raw.forecast_rate) + ")");
    }
    f.rate_hz = r;
  }
  const firmware::MonitorChannels& ch = config.settings.channels;
  for (const char* used : {ch.accel, ch.accel_batch, ch.wall_state, ch.alarm, ch.status, ch.wall_sensor,
                           ch.wall_estimate}) {
    if (f.channel == used) {
      throw UsageError((cli ? std::string("forecast.channel") : label + ".channel") + " " + options::quoted(f.channel) +
                       " is already one of the monitor's channels: every channel must be different");
    }
  }
  if (!config.walls.empty()) {
    throw UsageError(f.origin + ": the forecast follows one wall; the configuration's walls lists " +
                     std::to_string(config.walls.size()));
  }
  if (config.receive_path == ReceivePath::liblcm) throw UsageError(f.origin + " needs --receive-path own");
}

}  // namespace

MonitorParse parse_monitor_arguments(int argc, const char* const* argv) {
  CLI::App app{"Real-time monitor of an unreinforced masonry wall rocking out of plane: LCM ground-acceleration "
               "samples in, predicted wall state, alarm transitions and status out.",
               "rockwatch-monitor"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_arguments(app, argc, argv)) return MonitorParse{std::nullopt, *help};
  if (raw.version) return MonitorParse{std::nullopt, std::string("rockwatch-monitor ") + ROCKWATCH_VERSION + "\n"};

  MonitorConfig config;
  FileValues file;
  std::optional<ConfigReader> reader;
  if (options::given(app, "--config")) {
    if (raw.config.empty()) throw UsageError("--config needs a file name");
    config.config_path = raw.config;
    // Before reading: a FIFO would block, a device such as /dev/zero never ends, a directory is no file.
    options::check_input_file("--config", raw.config, "a JSON configuration file");
    reader.emplace(raw.config);
    file = reader->read();
  }
  const auto file_label = [&](const char* key) { return reader ? reader->key_label(key) : std::string(); };

  // Arithmetic and model: the fixed-point engine integrates the linear equation of motion only.
  Sourced<firmware::MonitorArithmetic> arith =
      pick(firmware::MonitorArithmetic::fixed_point, file.arith, file_label("arith"));
  if (options::given(app, "--arith")) arith = {parse_arith("--arith", raw.arith), "--arith"};
  config.settings.arithmetic = arith.value;
  Sourced<core::ModelKind> model = pick(core::ModelKind::linear, file.model, file_label("model"));
  if (options::given(app, "--model")) model = {options::parse_model("--model", raw.model), "--model"};
  if (model.value != core::ModelKind::linear && arith.value == firmware::MonitorArithmetic::fixed_point) {
    throw UsageError(name_of(model.origin, "--model") +
                     " full needs --arith double: the fixed-point engine supports the linear model only" +
                     (arith.origin.empty() ? std::string() : " (arith fixed from " + arith.origin + ")"));
  }
  config.settings.engine.model = model.value;

  // Restitution.
  // A wall file (--wall-file, else the configuration's wall_file): the base wall, and r unless --r or "r" is given.
  std::optional<options::WallFile> wall_file;
  if (options::given(app, "--wall-file")) {
    if (raw.wall.wall_file.empty()) throw UsageError("--wall-file needs a file name");
    wall_file = options::read_wall_file("--wall-file", raw.wall.wall_file);
  } else if (file.wall_file) {
    wall_file = options::read_wall_file(file_label("wall_file"), *file.wall_file);
  }
  core::Restitution file_r;
  std::string file_r_origin;
  if (wall_file) {
    file_r.kind = core::RestitutionKind::value;
    file_r.value = wall_file->r;
    file_r_origin = "the wall file";
  }
  Sourced<core::Restitution> r = pick(wall_file ? file_r : core::Restitution{}, file.r, file_label("r"));
  if (!file.r && wall_file) r.origin = file_r_origin;
  if (options::given(app, "--r")) r = {options::parse_restitution("--r", raw.r), "--r"};
  config.restitution = r.value;

  // Wall.
  firmware::WallEngineConfig& engine = config.settings.engine;
  engine.wall = merge_wall(app, raw, file, reader ? &*reader : nullptr, config.wall_origin, wall_file);
  check_wall_computable(engine.wall, r.value, model.value, config.wall_origin);
  engine.r_energy = core::restitution_energy_ratio(engine.wall, r.value);

  // Kappa (the engine takes [1, 100)).
  Sourced<double> kappa = pick(options::default_kappa(), file.kappa, file_label("kappa"));
  if (options::given(app, "--kappa")) kappa = {options::parse_kappa("--kappa", raw.kappa), "--kappa"};
  check_range(kappa.value >= 1.0, name_of(kappa.origin, "kappa"), ">= 1: collapse cannot come before x_inst",
              kappa.value);
  check_range(kappa.value < 100.0, name_of(kappa.origin, "kappa"), "< 100 (the fixed-point engine's range)",
              kappa.value);
  engine.kappa = kappa.value;

  // Alarm.
  const core::AlarmSettings alarm_defaults{};
  Sourced<double> lambda_w = pick(alarm_defaults.lambda_warning, file.lambda_w, file_label("alarm.lambda_w"));
  Sourced<double> hold = pick(alarm_defaults.hold_s, file.hold_s, file_label("alarm.hold_s"));
  Sourced<double> margin = pick(alarm_defaults.energy_margin, file.energy_margin, file_label("alarm.energy_margin"));
  Sourced<double> horizon =
      pick(alarm_defaults.imminent_horizon_s, file.imminent_horizon_s, file_label("alarm.imminent_horizon_s"));
  Sourced<double> energy_min_x =
      pick(alarm_defaults.energy_min_x, file.energy_min_x, file_label("alarm.energy_min_x"));
  if (options::given(app, "--lambda-w")) {
    lambda_w = {options::parse_finite_number("--lambda-w", raw.alarm.lambda_w), "--lambda-w"};
  }
  if (options::given(app, "--alarm-hold")) {
    hold = {options::parse_finite_number("--alarm-hold", raw.alarm.hold), "--alarm-hold"};
  }
  if (options::given(app, "--energy-margin")) {
    margin = {options::parse_finite_number("--energy-margin", raw.alarm.margin), "--energy-margin"};
  }
  if (options::given(app, "--imminent-horizon")) {
    horizon = {options::parse_finite_number("--imminent-horizon", raw.alarm.horizon), "--imminent-horizon"};
  }
  if (options::given(app, "--energy-min-x")) {
    energy_min_x = {options::parse_finite_number("--energy-min-x", raw.alarm.energy_min_x), "--energy-min-x"};
  }
  options::check_lambda_w(name_of(lambda_w.origin, "lambda_w"), lambda_w.value);
  options::check_alarm_hold(name_of(hold.origin, "hold_s"), hold.value);
  options::check_energy_margin(name_of(margin.origin, "energy_margin"), margin.value);
  options::check_imminent_horizon(name_of(horizon.origin, "imminent_horizon_s"), horizon.value);
  options::check_energy_min_x(name_of(energy_min_x.origin, "energy_min_x"), energy_min_x.value);
  engine.alarm.lambda_warning = lambda_w.value;
  engine.alarm.hold_s = hold.value;
  engine.alarm.energy_margin = margin.value;
  // The look-ahead (0 = off) in both engines: the fixed-point indicators evaluate it as the double ones do
  // (core/fixed_instability_indicators.hpp), so `--arith fixed` is `simulate --arith fixed --imminent-horizon`.
  engine.alarm.imminent_horizon_s = horizon.value;
  // The energy rule's displacement (0 = everywhere), likewise in both engines' indicators.
  engine.alarm.energy_min_x = energy_min_x.value;

  // Timing and input checks.
  firmware::MonitorSettings& s = config.settings;
  Sourced<double> rate = pick(s.sample_rate_hz, file.sample_rate_hz, file_label("sample_rate_hz"));
  if (options::given(app, "--rate")) rate = {options::parse_positive_number("--rate", raw.rate, " Hz"), "--rate"};
  check_range(rate.value > 0.0 && rate.value <= 10000.0 && 1.0 / rate.value <= 0.03,
              name_of(rate.origin, "sample_rate_hz"),
              "in (0, 10000] Hz with 1/rate <= 0.03 s, the engine's largest step (so at least 33.34 Hz)", rate.value);
  s.sample_rate_hz = rate.value;
  config.rate_origin = name_of(rate.origin, "sample_rate_hz");
  Sourced<double> max_step = pick(engine.max_step_s, file.max_step_s, file_label("max_step_s"));
  if (options::given(app, "--max-step")) {
    max_step = {options::parse_positive_number("--max-step", raw.max_step, " s"), "--max-step"};
  }
  check_range(max_step.value > 0.0 && max_step.value <= 0.03 &&
                  core::substeps_per_sample(1.0 / rate.value, max_step.value) != 0,
              name_of(max_step.origin, "max_step_s"),
              "in (0, 0.03] s and at least 1/(64 * rate) (at most 64 sub-steps per sample; " +
                  std::string(config.rate_origin) + " gives the rate)",
              max_step.value);
  engine.max_step_s = max_step.value;
  // The bridge: the file's, or about kDefaultBridge_s of samples at this rate (SPEC §12), within [10, 1000].
  s.max_bridge_samples = file.max_bridge_samples
                             ? *file.max_bridge_samples
                             : static_cast<std::int32_t>(
                                   std::clamp(std::lround(firmware::kDefaultBridge_s * rate.value), 10L, 1000L));
  if (file.sensor_range_mps2) {
    check_range(*file.sensor_range_mps2 > 0.0 && *file.sensor_range_mps2 <= 80.0, file_label("sensor_range_mps2"),
                "in (0, 80] m/s2 (80: the fixed-point engine's input limit)", *file.sensor_range_mps2);
    s.sensor_range_mps2 = *file.sensor_range_mps2;
  }
  if (file.late_limit_s) {
    check_range(*file.late_limit_s > 0.0 && *file.late_limit_s <= 60.0, file_label("late_limit_s"), "in (0, 60] s",
                *file.late_limit_s);
    s.late_limit_s = *file.late_limit_s;
  }
  // The clock tolerance, in whole µs in the loop: at least 1 µs, at most a day.
  Sourced<double> tolerance = pick(firmware::kDefaultClockTolerance_us * 1e-6, file.clock_tolerance_s,
                                   file_label("clock_tolerance_s"));
  if (options::given(app, "--clock-tolerance")) {
    tolerance = {options::parse_positive_number("--clock-tolerance", raw.clock_tolerance, " s"), "--clock-tolerance"};
  }
  check_range(tolerance.value >= 1e-6 && tolerance.value <= firmware::kMaxClockTolerance_us * 1e-6,
              name_of(tolerance.origin, "clock_tolerance_s"), "in [0.000001, 86400] s (1 us to one day)",
              tolerance.value);
  s.clock_tolerance_us = std::llround(tolerance.value * 1e6);
  // The engine's work budget per sample (carry-over, docs/FIXED_POINT.md): off on a host, which has the time.
  Sourced<double> budget = pick(0.0, file.work_budget_units, file_label("work_budget_units"));
  if (options::given(app, "--work-budget")) {
    budget = {options::parse_finite_number("--work-budget", raw.work_budget), "--work-budget"};
  }
  check_range(budget.value == 0.0 || (budget.value >= double(core::kMinWorkBudgetUnits) && budget.value <= 1e9 &&
                                      budget.value == std::floor(budget.value)),
              name_of(budget.origin, "work_budget_units"),
              "0 (off) or a whole number in [" + std::to_string(core::kMinWorkBudgetUnits) +
                  ", 1000000000] (the least fits one sample with one located event; the Cortex-M4 firmware runs " +
                  std::to_string(core::kDefaultWorkBudgetUnits) + ")",
              budget.value);
  if (budget.value != 0.0 && s.arithmetic != firmware::MonitorArithmetic::fixed_point) {
    throw UsageError(name_of(budget.origin, "work_budget_units") +
                     " applies to the fixed-point engine (--arith fixed): the double engine is not metered");
  }
  engine.work_budget_units = static_cast<std::int32_t>(budget.value);
  Sourced<core::WorkOverflow> overflow = pick(core::WorkOverflow::shed, file.work_overflow, file_label("work_overflow"));
  if (options::given(app, "--work-overflow")) {
    overflow = {options::parse_work_overflow("--work-overflow", raw.work_overflow), "--work-overflow"};
  }
  if (!overflow.origin.empty() && engine.work_budget_units == 0) {
    throw UsageError(name_of(overflow.origin, "work_overflow") +
                     " applies with a work budget (--work-budget or work_budget_units): without one nothing waits");
  }
  engine.work_overflow = overflow.value;

  // The wall observer: the file's observer object, enabled there or by --observer.
  const bool observer = raw.observer || file.observer_enabled.value_or(false);
  engine.observer_enabled = observer;
  for (int i = 0; i < kObserverFieldCount; ++i) {
    if (file.observer[i]) engine.observer.*kObserverFields[i].member = *file.observer[i];
  }
  if (file.observer_noise_learn_readings) engine.observer.noise_learn_readings = *file.observer_noise_learn_readings;
  if (observer && core::validate_observer_options(engine.observer) != core::ObserverError::ok) {
    throw UsageError(file_label("observer") + ": " +
                     core::observer_error_message(core::validate_observer_options(engine.observer)));
  }

  // Channels: printable names that fit the firmware's buffers, all different (the wall-sensor pair only counts with
  // the observer, as in the firmware's check).
  std::string channel_names[7] = {s.channels.accel,  s.channels.accel_batch, s.channels.wall_state,   s.channels.alarm,
                                  s.channels.status, s.channels.wall_sensor, s.channels.wall_estimate};
  for (int i = 0; i < 7; ++i) {
    if (!file.channels[i]) continue;
    const std::string key = std::string("channels.") + kChannelKeys[i];
    if (!channel_text_ok(*file.channels[i])) {
      throw UsageError(reader->key_label(key) + " must be 1 to " + std::to_string(firmware::kChannelNameMax - 1) +
                       " printable ASCII characters without spaces (got " + options::quoted(*file.channels[i]) + ")");
    }
    channel_names[i] = *file.channels[i];
  }
  const int n_channels = observer ? 7 : 5;
  for (int i = 0; i < n_channels; ++i) {
    for (int j = 0; j < i; ++j) {
      if (channel_names[i] == channel_names[j]) {
        throw UsageError((reader ? reader->key_label(std::string("channels.") + kChannelKeys[i])
                                 : std::string("channels.") + kChannelKeys[i]) +
                         " is " + options::quoted(channel_names[i]) + ", the same as channels." + kChannelKeys[j] +
                         ": every channel must be different");
      }
    }
  }
  char(*fields[7])[firmware::kChannelNameMax] = {&s.channels.accel,  &s.channels.accel_batch, &s.channels.wall_state,
                                                 &s.channels.alarm,  &s.channels.status,      &s.channels.wall_sensor,
                                                 &s.channels.wall_estimate};
  for (int i = 0; i < 7; ++i) set_channel(*fields[i], channel_names[i]);

  // LCM URL and mode.
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') {
    config.lcm_url = env;
    config.lcm_url_origin = "$LCM_DEFAULT_URL";
  }
  if (file.lcm_url) {
    config.lcm_url = *file.lcm_url;
    config.lcm_url_origin = file_label("lcm_url");
  }
  if (options::given(app, "--lcm-url")) {
    if (raw.lcm_url.empty()) throw UsageError("--lcm-url needs a URL, e.g. udpm://239.255.76.67:7667?ttl=0");
    config.lcm_url = raw.lcm_url;
    config.lcm_url_origin = "--lcm-url";
  }
  const bool in_given = options::given(app, "--offline-in"), out_given = options::given(app, "--offline-out");
  if (in_given != out_given) {
    throw UsageError(in_given ? "--offline-in needs --offline-out (the log the published messages go to)"
                              : "--offline-out needs --offline-in (the log to read)");
  }
  if (in_given) {
    if (raw.offline_in.empty()) throw UsageError("--offline-in needs a file name");
    if (raw.offline_out.empty()) throw UsageError("--offline-out needs a file name");
    if (raw.offline_in == raw.offline_out) {
      throw UsageError("--offline-out must differ from --offline-in (got " + options::quoted(raw.offline_out) + " for both)");
    }
    if (options::given(app, "--lcm-url")) throw UsageError("--lcm-url has no effect in offline mode (--offline-in)");
    config.offline_in = raw.offline_in;
    config.offline_out = raw.offline_out;
  }
  if (options::given(app, "--log")) {
    if (raw.log.empty()) throw UsageError("--log needs a file name");
    if (in_given) throw UsageError("--log is for live mode: offline mode writes its outputs to --offline-out");
    // Not a FIFO (opening it would block until a reader comes) or a directory. A character device is allowed: the
    // monitor never removes its log, and /dev/null (no log) or /dev/full (the full-disk test) are meaningful.
    struct stat st {};
    if (::stat(raw.log.c_str(), &st) == 0 && (S_ISFIFO(st.st_mode) || S_ISDIR(st.st_mode))) {
      throw UsageError("--log " + raw.log + ": is " + options::file_kind_text(st.st_mode) +
                       ", not a file: give the name of a file to write");
    }
    config.log_path = raw.log;
  }
  if (file.accept_from) config.accept_from = *file.accept_from;
  if (options::given(app, "--accept-from")) {
    config.accept_from.clear();
    for (const std::string& text : raw.accept_from) {
      SourceNetwork n;
      if (!parse_source_network(text, &n)) {
        throw UsageError("--accept-from: expected an IPv4 address or network such as 192.168.1.20 or 10.0.0.0/24, got " +
                         options::quoted(text));
      }
      config.accept_from.push_back(n);
    }
  }
  if (!config.accept_from.empty() && in_given) {
    throw UsageError("--accept-from (or accept_from) is for live mode: an offline log has no datagram sources");
  }
  if (raw.receive_path == "liblcm") {
    config.receive_path = ReceivePath::liblcm;
    if (!config.accept_from.empty()) throw UsageError("--accept-from needs --receive-path own (liblcm reads the datagrams)");
    if (options::given(app, "--log")) throw UsageError("--log needs --receive-path own");
  } else if (raw.receive_path != "own") {
    throw UsageError("--receive-path: expected own or liblcm, got " + options::quoted(raw.receive_path));
  }
  // Timing of the live receive thread (monitor_run.cpp): the command line over the file.
  TimingSettings& timing = config.timing;
  if (file.realtime_priority) {
    timing.priority = static_cast<int>(*file.realtime_priority);
    timing.priority_origin = file_label("realtime_priority");
  }
  if (file.cpu) {
    timing.cpu = static_cast<int>(*file.cpu);
    timing.cpu_origin = file_label("cpu");
  }
  if (file.busy_poll_us) {
    timing.busy_poll_us = static_cast<int>(*file.busy_poll_us);
    timing.busy_poll_origin = file_label("busy_poll_us");
  }
  if (options::given(app, "--realtime")) {
    timing.priority = options::parse_realtime_priority("--realtime", raw.timing.realtime);
    timing.priority_origin = "--realtime";
  }
  if (options::given(app, "--cpu")) {
    timing.cpu = options::parse_cpu("--cpu", raw.timing.cpu);
    timing.cpu_origin = "--cpu";
  }
  if (options::given(app, "--busy-poll-us")) {
    timing.busy_poll_us = options::parse_busy_poll_us("--busy-poll-us", raw.timing.busy_poll_us);
    timing.busy_poll_origin = "--busy-poll-us";
  }
  if (timing.any() && in_given) {
    throw UsageError(timing.first_origin() +
                     " is for live mode: offline mode reads a log as fast as it can, with no receive thread to schedule");
  }
  if (timing.busy_poll_us > 0 && config.receive_path == ReceivePath::liblcm) {
    throw UsageError(timing.busy_poll_origin + " needs --receive-path own (liblcm owns its socket)");
  }
  config.print_config = raw.print_config;
  if (file.walls) {
    expand_monitor_walls(config, *file.walls, reader->key_label("walls"));
    if (config.receive_path == ReceivePath::liblcm) throw UsageError("walls needs --receive-path own");
  }
  merge_forecast(app, raw, file, file_label("forecast"), config);

  config.normalised = normalised_settings(config);
  config.settings.config_digest = static_cast<std::int64_t>(fnv1a64(config.normalised.dump()));
  for (WallMonitorConfig& w : config.walls) w.settings.config_digest = config.settings.config_digest;
  return MonitorParse{std::move(config), {}};
}

}  // namespace rockwatch::monitor
