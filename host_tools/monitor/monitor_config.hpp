// The settings of `rockwatch-monitor`: a JSON configuration file (--config) merged with the command line, which
// overrides it. Every value is validated at start; a mistake throws options::UsageError naming the option or the key path
// in the file ("--config FILE: alarm.lambda_w ...") and what was expected.
//
// Configuration file keys (all optional; the defaults are the command line's):
//   wall {b, h1, h2, rho, fp, a, a_prime, g}     fields of the paper wall to replace (m, kg/m3, N/m, -, m/s2)
//   r            "ana" | "exp" | "impulse" | a number in [0, 1]     (--r; default exp)
//   arith        "fixed" (default) | "double"                          (--arith)
//   model        "linear" | "full" (full with arith "double" only)     (--model)
//   kappa        number in [1, 100)                                   (--kappa; default 2)
//   alarm {lambda_w, hold_s, energy_margin, imminent_horizon_s, energy_min_x}  (--lambda-w, --alarm-hold,
//                --energy-margin, --imminent-horizon, --energy-min-x; the horizon and energy_min_x: 0 = off, in the
//                settings and the digest only when on)
//   sample_rate_hz (--rate), max_bridge_samples, sensor_range_mps2, late_limit_s
//   channels {accel, accel_batch, wall_state, alarm, status, wall_sensor, wall_estimate}
//   observer {enabled, x_noise_m, a_noise_mps2, process_accel_mps2, gate_chi2, dropout_s, max_age_s, capacity_sigmas,
//             accel_inform_peak_noises, doubt_nis, quiet_motion_spread_noises, model_form_sigma,
//             doubt_model_form_sigma, capacity_min_x, doubt_capacity_min_x, capacity_correlation,
//             noise_learn_readings}
//                the wall observer (--observer enables it with these or the defaults); in the digest only when on
//   clock_tolerance_s (--clock-tolerance; default 10): the firmware's MonitorSettings::clock_tolerance_us, in seconds
//   realtime_priority (--realtime), cpu (--cpu), busy_poll_us (--busy-poll-us): the live receive thread's timing
//                (TimingSettings; not in the digest: they change when, not what, the monitor computes)
//   lcm_url      (--lcm-url)
//   accept_from  (--accept-from) ["ADDR" or "ADDR/PREFIX", ...]: the only sources of input datagrams (default: any)
//   walls        [{name, wall {...}, r, channels {accel, accel_batch, wall_sensor}}, ...]: one monitor, many walls
//                (monitor_walls.hpp): each wall the settings above with its own wall fields and r, its outputs on the
//                channels above suffixed _NAME (the wall named "wall": unsuffixed), its inputs shared unless given
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/core/restitution.hpp"
#include "datagram_input.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"

namespace rockwatch::monitor {

// The LCM URL when neither --lcm-url nor lcm_url nor $LCM_DEFAULT_URL gives one: multicast that stays on this machine.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

// Where the live monitor's input comes from: its own checked receive path (default), or liblcm's subscription
// (--receive-path liblcm: only for measuring the two side by side; liblcm 1.3.1 crashes on crafted datagrams).
enum class ReceivePath { own, liblcm };

// What the live monitor asks of Linux for its receive and processing thread (rockwatch/process/realtime.hpp), and
// where each came from ("--realtime", "--config FILE: realtime_priority") for the messages about it.
struct TimingSettings {
  int priority = 0;      // SCHED_FIFO priority; 0: ordinary scheduling, memory not locked
  int cpu = -1;          // pin to this CPU; -1: not pinned
  int busy_poll_us = 0;  // SO_BUSY_POLL on the receive socket; 0: not set
  std::string priority_origin, cpu_origin, busy_poll_origin;
  bool any() const { return priority > 0 || cpu >= 0 || busy_poll_us > 0; }
  const std::string& first_origin() const {
    return priority > 0 ? priority_origin : cpu >= 0 ? cpu_origin : busy_poll_origin;
  }
};

// --forecast / the file's forecast object (monitor_forecast.hpp): the live ensemble forecast of collapse.
inline constexpr const char* kDefaultForecastChannel = "ROCKWATCH_WALL_FORECAST";
inline constexpr double kDefaultForecastRate_hz = 10.0;
inline constexpr double kForecastRateMin_hz = 0.1, kForecastRateMax_hz = 100.0;

struct ForecastConfig {
  bool enabled = false;
  int members = 200;
  double horizon_s = 5.0;
  double rate_hz = kDefaultForecastRate_hz;
  std::uint64_t seed = 29;
  std::string channel = kDefaultForecastChannel;
  std::string origin;  // "--forecast", "--config FILE: forecast": for messages
  // --forecast-calibration / forecast.calibration: the recalibration's coefficients c0..c4 (SPEC §10 "Calibrated P";
  // four given: c4 = 0); none: the shipped ones (sim::default_forecast_calibration), applied only at the horizon they
  // were fitted at.
  std::optional<std::array<double, 5>> calibration;
};

// One wall of a `walls` configuration (monitor_walls.hpp).
struct WallMonitorConfig {
  std::string name;                      // [A-Za-z0-9_-], 1 to 24 characters; "wall": the unsuffixed channels
  firmware::MonitorSettings settings{};  // the top-level settings with this wall's wall, r and channels
  core::Restitution restitution{};
  std::string wall_origin;
};

struct MonitorConfig {
  firmware::MonitorSettings settings{};  // everything the loop needs; settings.config_digest set
  core::Restitution restitution{};       // the choice behind settings.engine.r_energy
  std::string lcm_url = kDefaultLcmUrl;
  std::string lcm_url_origin = "default";  // "--lcm-url", "--config FILE: lcm_url", "$LCM_DEFAULT_URL", "default"
  std::string config_path;               // empty without --config
  std::optional<std::string> offline_in, offline_out;  // offline mode: read one LCM log, write another
  ReceivePath receive_path = ReceivePath::own;  // --receive-path (command line only; not in the digest)
  std::vector<SourceNetwork> accept_from;  // --accept-from / accept_from: sources of input datagrams; empty = any
  TimingSettings timing;                 // --realtime, --cpu, --busy-poll-us (live mode; not in the digest)
  std::optional<std::string> log_path;   // live mode: the monitor's own LCM log of its inputs and outputs (--log)
  bool print_config = false;             // --print-config: print the normalised settings and exit
  std::string rate_origin = "default";   // where sample_rate_hz came from, for the engine's messages
  std::string wall_origin = "paper wall";
  nlohmann::json normalised;             // the settings that determine the outputs (config_digest hashes them)
  std::vector<WallMonitorConfig> walls;  // the `walls` key: one loop each; empty: the one wall of `settings`
  ForecastConfig forecast;               // --forecast N,H / forecast {...}: off by default
};

struct MonitorParse {
  std::optional<MonitorConfig> config;  // empty when --help or --version was asked for
  std::string text;                     // the help or version text
};

// Parses the command line (and the --config file it names). Throws options::UsageError.
MonitorParse parse_monitor_arguments(int argc, const char* const* argv);

// The normalised settings as one JSON object with sorted keys, and its FNV-1a 64 digest (over the compact dump).
nlohmann::json normalised_settings(const MonitorConfig& config);
std::uint64_t fnv1a64(const std::string& bytes, std::uint64_t hash = 14695981039346656037ull);
std::string digest_hex(std::int64_t digest);  // "0x0123456789abcdef"

// Copies a channel name into a fixed MonitorChannels field; false when it does not fit (64 bytes with the NUL).
bool set_channel(char (&field)[firmware::kChannelNameMax], const std::string& name);

}  // namespace rockwatch::monitor
