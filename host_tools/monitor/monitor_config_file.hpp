// rockwatch-monitor's configuration file (--config FILE, JSON): what it may set (FileValues), the tables of its wall,
// channel and observer keys, and the reader that checks every key and value, naming the key at fault. Part of the
// settings (monitor_config.hpp): parse_monitor_arguments merges these values with the command line's.
#pragma once

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <climits>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "monitor_command_line.hpp"
#include "monitor_config.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/realtime_options.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"

namespace rockwatch::monitor::config_detail {

// The forecast's member range (sim::kForecastMembersMin/Max; not included here, so the settings need no sim header).
inline constexpr long long sim_members_min = 1, sim_members_max = 100000;

using nlohmann::json;
using options::number_text;
using options::UsageError;


// What the file set; absent keys keep the defaults.
// The observer keys a configuration may give (kObserverFields below).
inline constexpr int kObserverFieldCount = 15;

struct FileValues {
  std::optional<double> wall[8];  // in kWallFields order
  std::optional<std::string> wall_file;  // a wall file (rockwatch/options/wall_file.hpp), relative to the config's folder
  std::optional<core::Restitution> r;
  std::optional<core::ModelKind> model;
  std::optional<firmware::MonitorArithmetic> arith;
  std::optional<double> kappa, lambda_w, hold_s, energy_margin, imminent_horizon_s, energy_min_x, sample_rate_hz,
      max_step_s, sensor_range_mps2, late_limit_s, clock_tolerance_s, work_budget_units;
  std::optional<core::WorkOverflow> work_overflow;
  std::optional<long long> realtime_priority, cpu, busy_poll_us;  // range-checked when read
  std::optional<std::int32_t> max_bridge_samples;
  std::optional<std::string> channels[7];
  std::optional<std::string> lcm_url;
  // observer {...}: enabled, then the options in kObserverFields order.
  std::optional<bool> observer_enabled;
  std::optional<double> observer[kObserverFieldCount];
  std::optional<std::int32_t> observer_noise_learn_readings;  // a whole number: not one of kObserverFields (doubles)
  std::optional<std::vector<SourceNetwork>> accept_from;
  std::optional<json> walls;  // checked by expand_monitor_walls (monitor_walls.cpp)
  // forecast {...} (monitor_forecast.hpp): each value range-checked when read.
  std::optional<bool> forecast_enabled;
  std::optional<int> forecast_members;
  std::optional<double> forecast_horizon_s, forecast_rate_hz;
  std::optional<std::uint64_t> forecast_seed;
  std::optional<std::string> forecast_channel;
  std::optional<std::array<double, 5>> forecast_calibration;  // c0..c4 (SPEC §10 "Calibrated P")
};

struct WallField {
  const char* key;     // the file's key under "wall" (core::validate_wall's field name)
  const char* option;  // the command-line option
  double core::WallParameters::*member;
  std::string options::WallOptionTexts::*text;
  const char* unit;
};

inline constexpr WallField kWallFields[8] = {
    {"b", "--b", &core::WallParameters::b_m, &options::WallOptionTexts::b, "m"},
    {"h1", "--h1", &core::WallParameters::h1_m, &options::WallOptionTexts::h1, "m"},
    {"h2", "--h2", &core::WallParameters::h2_m, &options::WallOptionTexts::h2, "m"},
    {"rho", "--rho", &core::WallParameters::rho_kgpm3, &options::WallOptionTexts::rho, "kg/m3"},
    {"fp", "--fp", &core::WallParameters::fp_npm, &options::WallOptionTexts::fp, "N/m"},
    {"a", "--a", &core::WallParameters::a, &options::WallOptionTexts::a, "fraction of b"},
    {"a_prime", "--a-prime", &core::WallParameters::a_prime, &options::WallOptionTexts::a_prime, "fraction of b"},
    {"g", "--g", &core::WallParameters::g_mps2, &options::WallOptionTexts::g, "m/s2"},
};

// The last two exist only with the observer.
inline constexpr const char* kChannelKeys[7] = {"accel", "accel_batch", "wall_state", "alarm", "status", "wall_sensor",
                                         "wall_estimate"};

// The observer's settings a configuration may give (the others keep core::ObserverOptions' defaults).
struct ObserverField {
  const char* key;  // under "observer"
  double core::ObserverOptions::*member;
  const char* unit;
};
inline constexpr ObserverField kObserverFields[kObserverFieldCount] = {
    {"x_noise_m", &core::ObserverOptions::x_noise_m, "m"},
    {"a_noise_mps2", &core::ObserverOptions::a_noise_mps2, "m/s2"},
    {"process_accel_mps2", &core::ObserverOptions::process_accel_mps2, "m/s2"},
    {"gate_chi2", &core::ObserverOptions::gate_chi2, "-"},
    {"dropout_s", &core::ObserverOptions::dropout_s, "s"},
    {"max_age_s", &core::ObserverOptions::max_age_s, "s"},
    {"capacity_sigmas", &core::ObserverOptions::alarm_capacity_sigmas, "-"},
    {"accel_inform_peak_noises", &core::ObserverOptions::accel_inform_peak_noises, "-"},
    {"doubt_nis", &core::ObserverOptions::doubt_nis, "-"},                                     // SPEC §11
    {"quiet_motion_spread_noises", &core::ObserverOptions::quiet_motion_spread_noises, "-"},  // SPEC §11
    {"model_form_sigma", &core::ObserverOptions::model_form_sigma, "-"},                      // SPEC §11
    {"doubt_model_form_sigma", &core::ObserverOptions::doubt_model_form_sigma, "-"},          // SPEC §11
    {"capacity_min_x", &core::ObserverOptions::capacity_min_x_fraction, "-"},                 // SPEC §11
    {"doubt_capacity_min_x", &core::ObserverOptions::doubt_capacity_min_x_fraction, "-"},     // SPEC §11
    {"capacity_correlation", &core::ObserverOptions::capacity_correlation, "-"},              // SPEC §11
};

inline std::string json_type(const json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean (" + v.dump() + ")";
  if (v.is_number()) return "a number (" + v.dump() + ")";
  if (v.is_string()) return "a string (" + options::quoted(v.get<std::string>()) + ")";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return v.type_name();
}

inline std::string join(const std::vector<std::string>& items, const char* separator) {
  std::string text;
  for (const std::string& s : items) text += (text.empty() ? "" : separator) + s;
  return text;
}

class ConfigReader {
 public:
  explicit ConfigReader(std::string path) : path_(std::move(path)), label_("--config " + path_) {}

  FileValues read() {
    const json root = parse();
    if (!root.is_object()) fail("the top level", "expected a JSON object {...}, got " + json_type(root));
    check_keys(root, "", {"arith", "wall", "wall_file", "r", "model", "kappa", "alarm", "sample_rate_hz", "max_step_s",
                          "max_bridge_samples", "sensor_range_mps2", "late_limit_s", "channels", "lcm_url",
                          "accept_from", "observer", "walls", "clock_tolerance_s", "work_budget_units", "work_overflow", "realtime_priority", "cpu",
                          "busy_poll_us", "forecast"});
    FileValues v;
    if (root.contains("wall")) read_wall(root.at("wall"), v);
    if (root.contains("r")) v.r = read_restitution(root.at("r"));
    if (root.contains("wall_file")) {
      const json& f = root.at("wall_file");
      if (!f.is_string() || f.get<std::string>().empty()) fail("wall_file", "expected a file name, got " + json_type(f));
      const std::filesystem::path given_path(f.get<std::string>());
      v.wall_file = given_path.is_absolute() ? given_path.string()
                                             : (std::filesystem::path(path_).parent_path() / given_path).string();
    }
    if (root.contains("arith")) v.arith = read_arith(root.at("arith"));
    if (root.contains("model")) v.model = read_model(root.at("model"));
    if (root.contains("kappa")) v.kappa = number(root.at("kappa"), "kappa", "");
    if (root.contains("alarm")) {
      const json& a = root.at("alarm");
      object(a, "alarm");
      check_keys(a, "alarm.", {"lambda_w", "hold_s", "energy_margin", "imminent_horizon_s", "energy_min_x"});
      if (a.contains("lambda_w")) v.lambda_w = number(a.at("lambda_w"), "alarm.lambda_w", "");
      if (a.contains("hold_s")) v.hold_s = number(a.at("hold_s"), "alarm.hold_s", " [s]");
      if (a.contains("energy_margin")) v.energy_margin = number(a.at("energy_margin"), "alarm.energy_margin", "");
      if (a.contains("imminent_horizon_s")) {
        v.imminent_horizon_s = number(a.at("imminent_horizon_s"), "alarm.imminent_horizon_s", " [s]");
      }
      if (a.contains("energy_min_x")) v.energy_min_x = number(a.at("energy_min_x"), "alarm.energy_min_x", "");
    }
    if (root.contains("sample_rate_hz")) v.sample_rate_hz = number(root.at("sample_rate_hz"), "sample_rate_hz", " [Hz]");
    if (root.contains("max_step_s")) v.max_step_s = number(root.at("max_step_s"), "max_step_s", " [s]");
    if (root.contains("max_bridge_samples")) v.max_bridge_samples = bridge(root.at("max_bridge_samples"));
    if (root.contains("sensor_range_mps2")) {
      v.sensor_range_mps2 = number(root.at("sensor_range_mps2"), "sensor_range_mps2", " [m/s2]");
    }
    if (root.contains("late_limit_s")) v.late_limit_s = number(root.at("late_limit_s"), "late_limit_s", " [s]");
    if (root.contains("work_budget_units")) {
      v.work_budget_units = number(root.at("work_budget_units"), "work_budget_units", " [Cortex-M4 instructions]");
    }
    if (root.contains("work_overflow")) v.work_overflow = read_work_overflow(root.at("work_overflow"));
    if (root.contains("clock_tolerance_s")) {
      v.clock_tolerance_s = number(root.at("clock_tolerance_s"), "clock_tolerance_s", " [s]");
    }
    if (root.contains("realtime_priority")) {
      v.realtime_priority = options::check_realtime_priority(
          key_label("realtime_priority"), whole(root.at("realtime_priority"), "realtime_priority", "a priority in 1..99"));
    }
    if (root.contains("cpu")) v.cpu = options::check_cpu(key_label("cpu"), whole(root.at("cpu"), "cpu", "a CPU number"));
    if (root.contains("busy_poll_us")) {
      v.busy_poll_us = options::check_busy_poll_us(
          key_label("busy_poll_us"), whole(root.at("busy_poll_us"), "busy_poll_us", "a whole number of microseconds"));
    }
    if (root.contains("channels")) {
      const json& c = root.at("channels");
      object(c, "channels");
      check_keys(c, "channels.", {kChannelKeys[0], kChannelKeys[1], kChannelKeys[2], kChannelKeys[3], kChannelKeys[4],
                                  kChannelKeys[5], kChannelKeys[6]});
      for (int i = 0; i < 7; ++i) {
        if (c.contains(kChannelKeys[i])) v.channels[i] = string(c.at(kChannelKeys[i]), std::string("channels.") + kChannelKeys[i]);
      }
    }
    if (root.contains("observer")) read_observer(root.at("observer"), v);
    if (root.contains("forecast")) read_forecast(root.at("forecast"), v);
    if (root.contains("walls")) v.walls = root.at("walls");
    if (root.contains("accept_from")) {
      const json& a = root.at("accept_from");
      if (!a.is_array()) fail("accept_from", "expected an array of \"ADDR\" or \"ADDR/PREFIX\" strings, got " + json_type(a));
      std::vector<SourceNetwork> networks;
      for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string key = "accept_from[" + std::to_string(i) + "]";
        const std::string text = string(a.at(i), key);
        SourceNetwork n;
        if (!parse_source_network(text, &n)) {
          fail(key, "expected an IPv4 address or network such as \"192.168.1.20\" or \"10.0.0.0/24\", got \"" + text + "\"");
        }
        networks.push_back(n);
      }
      v.accept_from = networks;
    }
    if (root.contains("lcm_url")) {
      v.lcm_url = string(root.at("lcm_url"), "lcm_url");
      if (v.lcm_url->empty()) fail("lcm_url", "expected an LCM URL such as \"udpm://239.255.76.67:7667?ttl=0\", got \"\"");
    }
    return v;
  }

  // "--config FILE: KEY" for messages about values.
  std::string key_label(const std::string& key) const { return label_ + ": " + key; }

 private:
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw UsageError(label_ + ": " + key + ": " + what);
  }

  json parse() const {
    std::ifstream in(path_, std::ios::binary);
    if (!in) throw UsageError(label_ + ": cannot read the file (" + std::strerror(errno) + ")");
    // A configuration is a few hundred bytes: more than 1 MiB is not one (and never read whole).
    constexpr std::size_t kMaxBytes = std::size_t{1} << 20;
    std::string text(kMaxBytes + 1, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    if (in.bad()) throw UsageError(label_ + ": cannot read the file");
    text.resize(static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxBytes) throw UsageError(label_ + ": larger than 1 MiB: not a configuration file");

    // nlohmann keeps the last of duplicate keys silently; a configuration with two values for one key is a mistake.
    struct Level {
      std::vector<std::string> seen;
      std::string current;
    };
    std::vector<Level> levels;
    std::optional<std::string> duplicate;
    const json::parser_callback_t callback = [&](int, json::parse_event_t event, json& parsed) {
      if (event == json::parse_event_t::object_start) {
        levels.emplace_back();
      } else if (event == json::parse_event_t::object_end) {
        if (!levels.empty()) levels.pop_back();
      } else if (event == json::parse_event_t::key && !levels.empty()) {
        Level& level = levels.back();
        level.current = parsed.get<std::string>();
        for (const std::string& s : level.seen) {
          if (s == level.current && !duplicate) {
            std::vector<std::string> path;
            for (const Level& l : levels) path.push_back(l.current);
            duplicate = join(path, ".");
          }
        }
        level.seen.push_back(level.current);
      }
      return true;
    };
    json root;
    try {
      root = json::parse(text, callback);
    } catch (const json::exception& e) {  // parse_error, and out_of_range for a number beyond double (1e400)
      std::string what = e.what();
      const std::size_t bracket = what.find("] ");
      if (what.rfind("[json.exception", 0) == 0 && bracket != std::string::npos) what = what.substr(bracket + 2);
      throw UsageError(label_ + ": not valid JSON: " + what);
    }
    if (duplicate) fail(*duplicate, "the key appears twice; give each key once");
    return root;
  }

  void object(const json& v, const std::string& key) const {
    if (!v.is_object()) fail(key, "expected an object {...}, got " + json_type(v));
  }

  void check_keys(const json& object_value, const std::string& prefix, const std::vector<std::string>& allowed) const {
    for (auto it = object_value.begin(); it != object_value.end(); ++it) {
      bool known = false;
      for (const std::string& a : allowed) known = known || a == it.key();
      if (!known) {
        throw UsageError(label_ + ": unknown key " + options::quoted(prefix + it.key()) + " (expected " +
                         (prefix.empty() ? "" : "under " + prefix.substr(0, prefix.size() - 1) + ": ") +
                         join(allowed, ", ") + ")");
      }
    }
  }

  double number(const json& v, const std::string& key, const std::string& unit) const {
    if (!v.is_number()) fail(key, "expected a number" + unit + ", got " + json_type(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "expected a finite number" + unit + ", got " + v.dump());
    return d;
  }

  std::string string(const json& v, const std::string& key) const {
    if (!v.is_string()) fail(key, "expected a string, got " + json_type(v));
    return v.get<std::string>();
  }

  // A whole number (1 and 1.0 alike; 1.5, "1" and true refused), within long long.
  long long whole(const json& v, const std::string& key, const std::string& expected) const {
    if (v.is_number_integer()) {
      if (v.is_number_unsigned() && v.get<std::uint64_t>() > 1000000000u) return 1000000001;  // out of every range
      return v.get<std::int64_t>();
    }
    if (v.is_number_float()) {
      const double d = v.get<double>();
      if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) <= 1e9) return static_cast<long long>(d);
    }
    fail(key, "expected " + expected + " (a whole number), got " + json_type(v));
  }

  std::int32_t bridge(const json& v) const {
    const char* key = "max_bridge_samples";
    if (!v.is_number_integer()) fail(key, "expected a whole number of samples in [0, 1000], got " + json_type(v));
    if (v.is_number_unsigned() ? v.get<std::uint64_t>() > 1000u : (v.get<std::int64_t>() < 0 || v.get<std::int64_t>() > 1000)) {
      fail(key, "must be in [0, 1000] samples (got " + v.dump() + ")");
    }
    return static_cast<std::int32_t>(v.get<std::int64_t>());
  }

  // Each value is checked on its own against core::validate_observer_options' ranges, so the message names its key.
  void read_observer(const json& o, FileValues& v) const {
    object(o, "observer");
    std::vector<std::string> keys{"enabled"};
    for (const ObserverField& f : kObserverFields) keys.emplace_back(f.key);
    keys.emplace_back("noise_learn_readings");
    check_keys(o, "observer.", keys);
    if (o.contains("noise_learn_readings")) {  // SPEC §11 "The transducer's noise"
      const json& n = o.at("noise_learn_readings");
      const char* key = "observer.noise_learn_readings";
      if (!n.is_number_integer()) fail(key, "expected a whole number of readings, got " + json_type(n));
      // The range is the core's (its message names it); beyond int32 the value is clamped to one it rejects.
      const std::int64_t wide = n.is_number_unsigned() && n.get<std::uint64_t>() > std::uint64_t(INT32_MAX)
                                    ? std::int64_t(INT32_MAX)
                                    : n.get<std::int64_t>();
      core::ObserverOptions options;
      options.noise_learn_readings = static_cast<std::int32_t>(std::clamp<std::int64_t>(wide, -1, INT32_MAX));
      const core::ObserverError err = core::validate_observer_options(options);
      if (err != core::ObserverError::ok) {
        fail(key, std::string(core::observer_error_message(err)) + " (got " + n.dump() + ")");
      }
      v.observer_noise_learn_readings = options.noise_learn_readings;
    }
    if (o.contains("enabled")) {
      const json& e = o.at("enabled");
      if (!e.is_boolean()) fail("observer.enabled", "expected true or false, got " + json_type(e));
      v.observer_enabled = e.get<bool>();
    }
    for (int i = 0; i < kObserverFieldCount; ++i) {
      const ObserverField& f = kObserverFields[i];
      if (!o.contains(f.key)) continue;
      const std::string key = std::string("observer.") + f.key;
      const double value = number(o.at(f.key), key, std::string(" [") + f.unit + "]");
      core::ObserverOptions options;
      options.*f.member = value;
      const core::ObserverError err = core::validate_observer_options(options);
      if (err != core::ObserverError::ok) {
        fail(key, std::string(core::observer_error_message(err)) + " (got " + o.at(f.key).dump() + ")");
      }
      v.observer[i] = value;
    }
  }

  // forecast {enabled, members, horizon_s, rate_hz, seed, channel, calibration}: the ranges of --forecast and --forecast-rate.
  void read_forecast(const json& f, FileValues& v) const {
    object(f, "forecast");
    check_keys(f, "forecast.", {"enabled", "members", "horizon_s", "rate_hz", "seed", "channel", "calibration"});
    if (f.contains("calibration")) {
      const json& c = f.at("calibration");
      if (!c.is_array() || (c.size() != 4 && c.size() != 5)) {
        fail("forecast.calibration",
             "expected an array of four or five numbers [c0, c1, c2, c3(, c4)], got " + c.dump());
      }
      std::array<double, 5> k{};  // four numbers: c4 = 0 (the first calibration's model)
      for (std::size_t i = 0; i < c.size(); ++i) k[i] = number(c.at(i), "forecast.calibration", "");
      v.forecast_calibration = k;
    }
    if (f.contains("enabled")) {
      const json& e = f.at("enabled");
      if (!e.is_boolean()) fail("forecast.enabled", "expected true or false, got " + json_type(e));
      v.forecast_enabled = e.get<bool>();
    }
    if (f.contains("members")) {
      const long long n = whole(f.at("members"), "forecast.members", "a number of members in [1, 100000]");
      if (n < sim_members_min || n > sim_members_max) {
        fail("forecast.members", "must be a whole number in [1, 100000] (got " + f.at("members").dump() + ")");
      }
      v.forecast_members = static_cast<int>(n);
    }
    if (f.contains("horizon_s")) {
      const double h = number(f.at("horizon_s"), "forecast.horizon_s", " [s]");
      if (!(h > 0.0 && h <= 60.0)) fail("forecast.horizon_s", "must be in (0, 60] s (got " + f.at("horizon_s").dump() + ")");
      v.forecast_horizon_s = h;
    }
    if (f.contains("rate_hz")) {
      const double r = number(f.at("rate_hz"), "forecast.rate_hz", " [Hz]");
      if (!(r >= kForecastRateMin_hz && r <= kForecastRateMax_hz)) {
        fail("forecast.rate_hz", "must be in [0.1, 100] Hz (got " + f.at("rate_hz").dump() + ")");
      }
      v.forecast_rate_hz = r;
    }
    if (f.contains("seed")) {
      const json& sd = f.at("seed");
      if (!sd.is_number_unsigned()) fail("forecast.seed", "expected a whole number from 0 to 2^64-1, got " + sd.dump());
      v.forecast_seed = sd.get<std::uint64_t>();
    }
    if (f.contains("channel")) v.forecast_channel = string(f.at("channel"), "forecast.channel");
  }

  void read_wall(const json& w, FileValues& v) const {
    object(w, "wall");
    std::vector<std::string> keys;
    for (const WallField& f : kWallFields) keys.emplace_back(f.key);
    check_keys(w, "wall.", keys);
    for (int i = 0; i < 8; ++i) {
      const WallField& f = kWallFields[i];
      if (w.contains(f.key)) v.wall[i] = number(w.at(f.key), std::string("wall.") + f.key, std::string(" [") + f.unit + "]");
    }
  }

  core::Restitution read_restitution(const json& v) const {
    const std::string expected = "expected \"ana\", \"exp\", \"impulse\" or an energy ratio in [0, 1], got ";
    core::Restitution r;
    if (v.is_string()) {
      const std::string s = v.get<std::string>();
      if (s != "ana" && s != "exp" && s != "impulse") fail("r", expected + json_type(v));
      return options::parse_restitution(key_label("r"), s);
    }
    if (!v.is_number()) fail("r", expected + json_type(v));
    const double value = v.get<double>();
    if (!(value >= 0.0 && value <= 1.0)) fail("r", expected + v.dump());
    r.kind = core::RestitutionKind::value;
    r.value = value;
    return r;
  }

  core::ModelKind read_model(const json& v) const {
    if (!v.is_string()) fail("model", "expected \"linear\" or \"full\", got " + json_type(v));
    return options::parse_model(key_label("model"), v.get<std::string>());
  }

  core::WorkOverflow read_work_overflow(const json& v) const {
    if (!v.is_string()) fail("work_overflow", "expected \"shed\" or \"finish\", got " + json_type(v));
    return options::parse_work_overflow(key_label("work_overflow"), v.get<std::string>());
  }

  firmware::MonitorArithmetic read_arith(const json& v) const {
    if (!v.is_string()) fail("arith", "expected \"fixed\" or \"double\", got " + json_type(v));
    return parse_arith(key_label("arith"), v.get<std::string>());
  }

  std::string path_;
  std::string label_;
};

}  // namespace rockwatch::monitor::config_detail
