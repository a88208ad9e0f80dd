#include "monitor_config.hpp"

#include <sys/stat.h>

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
#include "monitor_walls.hpp"

#ifndef ROCKWATCH_VERSION
#define ROCKWATCH_VERSION "unknown"
#endif

namespace rockwatch::monitor {

using options::number_text;
using options::UsageError;
using nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------------------------------
// Command line

struct RawOptions {
  std::string config, lcm_url, arith = "fixed", rate, max_step, offline_in, offline_out, log, receive_path = "own";
  std::string clock_tolerance;
  std::string work_budget, work_overflow;
  std::vector<std::string> accept_from;
  options::RealtimeOptionTexts timing;  // --realtime, --cpu, --busy-poll-us
  options::WallOptionTexts wall;
  std::string r = "exp", model = "linear", kappa;
  options::AlarmOptionTexts alarm;  // --lambda-w, --alarm-hold, --energy-margin (its arith and alarms are unused)
  bool print_config = false, version = false, observer = false;
};

const char* const kFooter =
    "Reads ground_accel_t / ground_accel_batch_t samples from LCM, runs the fixed-point rocking engine and the\n"
    "instability alarm once per sample, and publishes wall_state_t (every sample), alarm_event_t (every alarm level\n"
    "change) and monitor_status_t (once per second and on exit). Each alarm change is also printed on stdout as one\n"
    "JSON line: utime, seq, input_seq, level, previous (QUIET, ROCKING, WARNING, IMMINENT, COLLAPSED), reason (names)\n"
    "and reason_bits, x_m, xd_mps, energy_ratio, t_to_instability_s (null: the wall would turn back). On SIGINT or\n"
    "SIGTERM (or the end of an offline log) it publishes a final status, prints {\"summary\": {...}} as the last\n"
    "line on stdout and a human summary on stderr, and exits 0.\n"
    "\n"
    "Configuration file (--config, JSON; every key optional, unknown keys refused; the command line overrides it):\n"
    "  wall {b, h1, h2, rho, fp, a, a_prime, g}   fields replacing the paper wall's (as --b ... --g)\n"
    "  wall_file \"W.json\"   base wall and r from a wall file (rockwatch identify --wall-out; as --wall-file;\n"
    "    relative to the configuration's folder); the wall fields above and r replace its values\n"
    "  r \"ana\"|\"exp\"|\"impulse\"|number   model \"linear\"   kappa K\n"
    "  alarm {lambda_w, hold_s, energy_margin}   (as --lambda-w, --alarm-hold, --energy-margin)\n"
    "  sample_rate_hz (--rate, 200)   max_step_s (--max-step, 0.001)   max_bridge_samples (10)   sensor_range_mps2 (80)   late_limit_s (0.05)\n"
    "  work_budget_units (--work-budget, 0): the fixed-point engine's work per sample in Cortex-M4 instructions; a\n"
    "    sample whose work does not fit is finished (and published, with its own time) at later samples' calls.\n"
    "    0 on a host (every sample in its own call); 23000 runs as the Cortex-M4 firmware does\n"
    "  work_overflow (--work-overflow, \"shed\"): with a work budget, what the engine does when 64 samples wait:\n"
    "    \"shed\" (events no longer located; every call within the budget) or \"finish\" (the oldest sample finished\n"
    "    beyond the budget; the answers always as without a budget). Counted in the summary (samples_work_shed,\n"
    "    samples_over_budget)\n"
    "  clock_tolerance_s (--clock-tolerance, 10): samples stamped further than this from the monitor's clock have a\n"
    "    time it does not trust (counted, flagged, not used to detect publisher restarts)\n"
    "  channels {accel, accel_batch, wall_state, alarm, status, wall_sensor, wall_estimate}   (ROCKWATCH_ACCEL, ...)\n"
    "  observer {enabled, x_noise_m, a_noise_mps2, process_accel_mps2, gate_chi2, dropout_s, max_age_s}\n"
    "    the wall observer (--observer: enabled with the defaults): fuses wall_sensor_t samples (channel\n"
    "    wall_sensor) with the model, publishes wall_estimate_t (channel wall_estimate) and alarms on the fused state\n"
    "  lcm_url (--lcm-url; default $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0)\n"
    "  accept_from [\"ADDR\" or \"ADDR/PREFIX\", ...]   (--accept-from; sources of input datagrams, default any)\n"
    "  realtime_priority (--realtime)   cpu (--cpu)   busy_poll_us (--busy-poll-us)   live mode, not in the digest\n"
    "  walls [{name, wall {...}, r, channels {accel, accel_batch, wall_sensor}}, ...]   one monitor, up to 16 walls:\n"
    "    each the settings above with its own wall fields (replacing the top-level ones) and r; it publishes on the\n"
    "    output channels suffixed _NAME (ROCKWATCH_WALL_STATE_north, ROCKWATCH_ALARM_north, ROCKWATCH_STATUS_north;\n"
    "    the wall named \"wall\": unsuffixed) and reads the top-level ground channels (shared) unless given its own;\n"
    "    alarm lines on stdout name the wall (\"wall\"), the summary lists the walls\n"
    "\n"
    "Offline mode (--offline-in LOG --offline-out LOG): every event of the input log on the two input channels is\n"
    "fed to the loop in order with its log timestamp as the receive time; the messages published go to the output\n"
    "log with the timestamp of the input event that caused them; a status at the first event, at each whole second\n"
    "of log time after it and at the last event. Deterministic: the same input gives the same output, byte for byte.\n"
    "\n"
    "Exit status: 0 stopped by SIGINT/SIGTERM or end of the offline log, 2 invalid options, configuration or\n"
    "files (message naming the option or key), 1 runtime failure (LCM, writing the output log).\n"
    "\n"
    "Examples:\n"
    "  rockwatch-monitor --config wall.json\n"
    "  rockwatch-monitor --h1 1.5 --h2 1.5 --r ana --rate 100 --lcm-url 'udpm://239.255.76.67:7667?ttl=0'\n"
    "  rockwatch-monitor --offline-in sensor.lcmlog --offline-out monitor.lcmlog\n";

void add_options(CLI::App& app, RawOptions& raw) {
  app.add_option("--config", raw.config, "JSON configuration file (keys below); the command line overrides it")
      ->type_name("FILE");
  app.add_option("--lcm-url", raw.lcm_url, "LCM URL (default: the file's lcm_url, $LCM_DEFAULT_URL, "
                                           "udpm://239.255.76.67:7667?ttl=0)")
      ->type_name("URL");
  app.add_option("--arith", raw.arith,
                 "Engine arithmetic: fixed (default; the firmware's engine, = `rockwatch simulate --arith fixed`) | "
                 "double (= `rockwatch simulate --arith double`; linear or full model)")
      ->type_name("fixed|double");
  options::add_wall_options(app, raw.wall);
  options::add_restitution_option(app, raw.r);
  app.add_option("--model", raw.model, "Equation of motion: linear (default, the paper's; the fixed-point engine's "
                                       "only model) | full (with --arith double)")
      ->type_name("linear|full");
  options::add_kappa_option(app, raw.kappa);
  options::add_alarm_setting_options(app, raw.alarm, "");
  app.add_option("--rate", raw.rate, "Expected input sample rate [Hz] (default 200); the alarm runs once per sample")
      ->type_name("HZ");
  options::add_max_step_option(app, raw.max_step, "; the sample interval is 1/rate");
  app.add_option("--work-budget", raw.work_budget,
                 "The fixed-point engine's work per sample [Cortex-M4 instructions] (default 0: every sample finished "
                 "in its own call, as a host can afford); " + std::to_string(core::kDefaultWorkBudgetUnits) +
                     " runs as the Cortex-M4 firmware does: a sample whose work does not fit is published at later "
                     "samples' calls, the same answers later (carry-over)")
      ->type_name("UNITS");
  app.add_option("--work-overflow", raw.work_overflow,
                 "With --work-budget, what the engine does when 64 samples wait: shed (default; events no longer "
                 "located, every call within the budget) | finish (the oldest sample finished beyond the budget, the "
                 "answers as without a budget)")
      ->type_name("shed|finish");
  app.add_option("--clock-tolerance", raw.clock_tolerance,
                 "How far a sample's time may be from the monitor's clock at reception, ahead or behind [s] (default " +
                     options::number_text(firmware::kDefaultClockTolerance_us * 1e-6) +
                     "; up to 86400): a sample beyond it is counted and flagged (time untrusted) and its time is not "
                     "used to detect a publisher restart")
      ->type_name("S");
  app.add_option("--offline-in", raw.offline_in, "Offline mode: read this LCM log instead of listening")
      ->type_name("LOG");
  app.add_option("--offline-out", raw.offline_out, "Offline mode: write the published messages to this LCM log")
      ->type_name("LOG");
  app.add_option("--log", raw.log,
                 "Live mode: record every input message received and every message published to this LCM log "
                 "(written once per second; a full disk is reported and counted, monitoring goes on)")
      ->type_name("FILE");
  app.add_option("--accept-from", raw.accept_from,
                 "Live mode: accept input datagrams only from this IPv4 address or network (ADDR or ADDR/PREFIX; "
                 "repeatable; default: any source). Others are dropped and counted")
      ->type_name("ADDR[/PREFIX]");
  app.add_option("--receive-path", raw.receive_path,
                 "Live mode: own (default: the monitor's checked datagram path) or liblcm (liblcm's receive thread, "
                 "for measuring the two side by side only: it crashes on crafted datagrams)")
      ->type_name("own|liblcm");
  options::add_realtime_options(app, raw.timing, "the receive and processing thread (live mode)");
  app.add_flag("--observer", raw.observer,
               "Run the wall observer: fuse the wall sensors (wall_sensor_t) with the model, publish wall_estimate_t "
               "and alarm on the fused state (settings: the file's observer object, else the defaults)");
  app.add_flag("--print-config", raw.print_config,
               "Print the normalised settings and their digest as one JSON object and exit");
  app.add_flag("--version", raw.version, "Print the version and exit");
  app.footer(kFooter);
}

// As options::parse_command_line, with this program's name in the hint.
std::optional<std::string> parse_arguments(CLI::App& app, int argc, const char* const* argv) {
  const std::string hint = " (see rockwatch-monitor --help)";
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.help();
    const std::vector<std::string> extras = app.remaining();
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr && !extras.empty()) {
      const std::string& first = extras.front();
      const bool is_option = first.size() > 1 && first.front() == '-';
      throw UsageError(std::string(is_option ? "unknown option " : "unexpected argument ") + options::quoted(first) + hint);
    }
    throw UsageError(e.what() + hint);
  }
  return std::nullopt;
}

firmware::MonitorArithmetic parse_arith(const std::string& name, const std::string& text) {
  if (text == "fixed") return firmware::MonitorArithmetic::fixed_point;
  if (text == "double") return firmware::MonitorArithmetic::double_precision;
  throw UsageError(name + " must be fixed or double (got " + options::quoted(text) + ")");
}

const char* arith_name(firmware::MonitorArithmetic a) {
  return a == firmware::MonitorArithmetic::double_precision ? "double" : "fixed";
}

// ---------------------------------------------------------------------------------------------------------------
// Configuration file

// What the file set; absent keys keep the defaults.
struct FileValues {
  std::optional<double> wall[8];  // in kWallFields order
  std::optional<std::string> wall_file;  // a wall file (rockwatch/options/wall_file.hpp), relative to the config's folder
  std::optional<core::Restitution> r;
  std::optional<core::ModelKind> model;
  std::optional<firmware::MonitorArithmetic> arith;
  std::optional<double> kappa, lambda_w, hold_s, energy_margin, sample_rate_hz, max_step_s, sensor_range_mps2,
      late_limit_s, clock_tolerance_s, work_budget_units;
  std::optional<core::WorkOverflow> work_overflow;
  std::optional<long long> realtime_priority, cpu, busy_poll_us;  // range-checked when read
  std::optional<std::int32_t> max_bridge_samples;
  std::optional<std::string> channels[7];
  std::optional<std::string> lcm_url;
  // observer {...}: enabled, then the options in kObserverFields order.
  std::optional<bool> observer_enabled;
  std::optional<double> observer[6];
  std::optional<std::vector<SourceNetwork>> accept_from;
  std::optional<json> walls;  // checked by expand_monitor_walls (monitor_walls.cpp)
};

struct WallField {
  const char* key;     // the file's key under "wall" (core::validate_wall's field name)
  const char* option;  // the command-line option
  double core::WallParameters::*member;
  std::string options::WallOptionTexts::*text;
  const char* unit;
};

constexpr WallField kWallFields[8] = {
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
constexpr const char* kChannelKeys[7] = {"accel", "accel_batch", "wall_state", "alarm", "status", "wall_sensor",
                                         "wall_estimate"};

// The observer's settings a configuration may give (the others keep core::ObserverOptions' defaults).
struct ObserverField {
  const char* key;  // under "observer"
  double core::ObserverOptions::*member;
  const char* unit;
};
constexpr ObserverField kObserverFields[6] = {
    {"x_noise_m", &core::ObserverOptions::x_noise_m, "m"},
    {"a_noise_mps2", &core::ObserverOptions::a_noise_mps2, "m/s2"},
    {"process_accel_mps2", &core::ObserverOptions::process_accel_mps2, "m/s2"},
    {"gate_chi2", &core::ObserverOptions::gate_chi2, "-"},
    {"dropout_s", &core::ObserverOptions::dropout_s, "s"},
    {"max_age_s", &core::ObserverOptions::max_age_s, "s"},
};

std::string json_type(const json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean (" + v.dump() + ")";
  if (v.is_number()) return "a number (" + v.dump() + ")";
  if (v.is_string()) return "a string (" + options::quoted(v.get<std::string>()) + ")";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return v.type_name();
}

std::string join(const std::vector<std::string>& items, const char* separator) {
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
                          "busy_poll_us"});
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
      check_keys(a, "alarm.", {"lambda_w", "hold_s", "energy_margin"});
      if (a.contains("lambda_w")) v.lambda_w = number(a.at("lambda_w"), "alarm.lambda_w", "");
      if (a.contains("hold_s")) v.hold_s = number(a.at("hold_s"), "alarm.hold_s", " [s]");
      if (a.contains("energy_margin")) v.energy_margin = number(a.at("energy_margin"), "alarm.energy_margin", "");
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
    check_keys(o, "observer.", keys);
    if (o.contains("enabled")) {
      const json& e = o.at("enabled");
      if (!e.is_boolean()) fail("observer.enabled", "expected true or false, got " + json_type(e));
      v.observer_enabled = e.get<bool>();
    }
    for (int i = 0; i < 6; ++i) {
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

}  // namespace

bool set_channel(char (&field)[firmware::kChannelNameMax], const std::string& name) {
  if (name.size() >= firmware::kChannelNameMax) return false;
  std::memset(field, 0, sizeof field);
  std::memcpy(field, name.data(), name.size());
  return true;
}

std::uint64_t fnv1a64(const std::string& bytes, std::uint64_t hash) {
  for (const char c : bytes) {
    hash ^= static_cast<std::uint8_t>(c);
    hash *= 1099511628211ull;
  }
  return hash;
}

std::string digest_hex(std::int64_t digest) {
  static const char* const kDigits = "0123456789abcdef";
  const auto u = static_cast<std::uint64_t>(digest);
  std::string text = "0x";
  for (int shift = 60; shift >= 0; shift -= 4) text += kDigits[(u >> shift) & 0xFu];
  return text;
}

json normalised_settings(const MonitorConfig& config) {
  const firmware::MonitorSettings& s = config.settings;
  const core::WallParameters& w = s.engine.wall;
  json r;
  if (config.restitution.kind == core::RestitutionKind::value) {
    r = config.restitution.value;
  } else {
    r = core::restitution_name(config.restitution.kind);
  }
  json out{
      {"format", "rockwatch-monitor settings 1"},
      {"arith", arith_name(s.arithmetic)},
      {"wall", {{"b", w.b_m}, {"h1", w.h1_m}, {"h2", w.h2_m}, {"rho", w.rho_kgpm3}, {"fp", w.fp_npm}, {"a", w.a},
                {"a_prime", w.a_prime}, {"g", w.g_mps2}}},
      {"r", r},
      {"r_energy_ratio", s.engine.r_energy},
      {"model", s.engine.model == core::ModelKind::full ? "full" : "linear"},
      {"kappa", s.engine.kappa},
      {"alarm",
       {{"lambda_w", s.engine.alarm.lambda_warning}, {"hold_s", s.engine.alarm.hold_s},
        {"energy_margin", s.engine.alarm.energy_margin}}},
      {"sample_rate_hz", s.sample_rate_hz},
      {"max_step_s", s.engine.max_step_s},
      {"substeps", core::substeps_per_sample(1.0 / s.sample_rate_hz, s.engine.max_step_s)},
      {"max_bridge_samples", s.max_bridge_samples},
      {"sensor_range_mps2", s.sensor_range_mps2},
      {"late_limit_s", s.late_limit_s},
      {"restart_window", s.restart_window},
      {"channels",
       {{"accel", s.channels.accel}, {"accel_batch", s.channels.accel_batch}, {"wall_state", s.channels.wall_state},
        {"alarm", s.channels.alarm}, {"status", s.channels.status}}},
  };
  // The observer changes every output; absent when off, so that the digest of a configuration without it stays.
  if (s.engine.observer_enabled) {
    const core::ObserverOptions& o = s.engine.observer;
    out["observer"] = {{"enabled", true},
                       {"x_noise_m", o.x_noise_m},
                       {"a_noise_mps2", o.a_noise_mps2},
                       {"process_accel_mps2", o.process_accel_mps2},
                       {"gate_chi2", o.gate_chi2},
                       {"dropout_s", o.dropout_s},
                       {"max_age_s", o.max_age_s}};
    out["channels"]["wall_sensor"] = s.channels.wall_sensor;
    out["channels"]["wall_estimate"] = s.channels.wall_estimate;
  }
  // Many walls: each one's own settings; absent with one wall (the digest of such a configuration stays).
  if (!config.walls.empty()) out["walls"] = walls_json(config.walls);
  // The clock tolerance decides which times are trusted; absent at the default (the digest of existing configurations
  // stays).
  if (s.engine.work_budget_units != 0) out["work_budget_units"] = s.engine.work_budget_units;  // absent when off
  if (s.engine.work_overflow != core::WorkOverflow::shed) {  // absent at the default
    out["work_overflow"] = options::work_overflow_name(s.engine.work_overflow);
  }
  if (s.clock_tolerance_us != firmware::kDefaultClockTolerance_us) {
    out["clock_tolerance_s"] = static_cast<double>(s.clock_tolerance_us) * 1e-6;
  }
  // Which sources are accepted changes what the monitor processes; absent when any is (the default digest stays).
  if (!config.accept_from.empty()) {
    json a = json::array();
    for (const SourceNetwork& n : config.accept_from) a.push_back(source_network_text(n));
    out["accept_from"] = a;
  }
  return out;
}

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
  if (options::given(app, "--lambda-w")) {
    lambda_w = {options::parse_finite_number("--lambda-w", raw.alarm.lambda_w), "--lambda-w"};
  }
  if (options::given(app, "--alarm-hold")) {
    hold = {options::parse_finite_number("--alarm-hold", raw.alarm.hold), "--alarm-hold"};
  }
  if (options::given(app, "--energy-margin")) {
    margin = {options::parse_finite_number("--energy-margin", raw.alarm.margin), "--energy-margin"};
  }
  options::check_lambda_w(name_of(lambda_w.origin, "lambda_w"), lambda_w.value);
  options::check_alarm_hold(name_of(hold.origin, "hold_s"), hold.value);
  options::check_energy_margin(name_of(margin.origin, "energy_margin"), margin.value);
  engine.alarm.lambda_warning = lambda_w.value;
  engine.alarm.hold_s = hold.value;
  engine.alarm.energy_margin = margin.value;

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
  if (file.max_bridge_samples) s.max_bridge_samples = *file.max_bridge_samples;
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
  for (int i = 0; i < 6; ++i) {
    if (file.observer[i]) engine.observer.*kObserverFields[i].member = *file.observer[i];
  }
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

  config.normalised = normalised_settings(config);
  config.settings.config_digest = static_cast<std::int64_t>(fnv1a64(config.normalised.dump()));
  for (WallMonitorConfig& w : config.walls) w.settings.config_digest = config.settings.config_digest;
  return MonitorParse{std::move(config), {}};
}

}  // namespace rockwatch::monitor
