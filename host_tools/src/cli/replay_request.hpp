// What `rockwatch replay` was asked to do, parsed and validated from its command line: the record (the record options
// of `rockwatch simulate`), the rate it is resampled to, the sensor model, the pacing and where the samples go (LCM,
// an LCM log, a CSV of the samples).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "record_selection.hpp"

namespace rockwatch::cli {

inline constexpr const char* kAccelChannel = "ROCKWATCH_ACCEL";             // ground_accel_t
inline constexpr const char* kAccelBatchChannel = "ROCKWATCH_ACCEL_BATCH";  // ground_accel_batch_t
inline constexpr int kMaxBatchSamples = 50;                                 // ground_accel_batch_t::MAX_SAMPLES
inline constexpr double kMaxReplayRateHz = 10000.0;                         // the monitor's limit

// What a real accelerometer adds to the true ground acceleration, applied in this order to every sample:
// value = Q·round((a + bias + noise) / Q) with noise ~ N(0, noise_sd²); then the sample is dropped (not sent) with
// probability `dropout`. ü always; v̈ only when the input has a vertical (without one, v̈ = 0: no vertical sensor).
struct SensorModel {
  double noise_sd_mps2 = 0.0;
  std::uint64_t seed = 1;  // the noise and dropout draws (sim::synthesis::RandomStream: the same on every machine)
  double bias_mps2 = 0.0;
  double quantum_mps2 = 0.0;  // 0 = no quantisation
  double dropout = 0.0;       // in [0, 1)
  bool active() const { return noise_sd_mps2 > 0.0 || bias_mps2 != 0.0 || quantum_mps2 > 0.0 || dropout > 0.0; }
};

struct ReplayRequest {
  RecordSelection record;             // --record or --suite, --vertical, --units, --dt, ...
  std::optional<double> scale_pga_g;  // peak |ü| = G·g (g = 9.81 m/s²)
  double g_mps2 = 9.81;               // converts records in g and --scale-pga
  double rate_hz = 200.0;             // --rate: the samples sent per second of record time
  double speed = 1.0;                 // --speed: 1 real time, 2 twice as fast, 0 as fast as possible
  bool publish = true;                // over LCM (false: --log without --lcm-url)
  std::string lcm_url;
  std::string channel;  // --lcm-channel, default by message type
  int batch = 0;        // --batch N: ground_accel_batch_t of up to N samples; 0 = ground_accel_t
  SensorModel sensor;
  std::optional<std::string> log_path;          // --log FILE: a standard LCM log of the messages
  std::optional<std::string> samples_out_path;  // --samples-out FILE: the samples as sent, CSV
  bool json = false;
};

struct ReplayParse {
  std::optional<ReplayRequest> request;  // empty for --help
  std::string help_text;
};

// Parses `rockwatch replay` arguments (argv[0] is the command name). Throws UsageError naming the option at fault.
ReplayParse parse_replay_arguments(int argc, const char* const* argv);

// The sample period in whole microseconds that --batch needs (ground_accel_batch_t::sample_period_us), or nullopt
// when 1/rate is not a whole number of microseconds.
std::optional<std::int32_t> whole_period_us(double rate_hz);

}  // namespace rockwatch::cli
