// The samples `rockwatch replay` (and `rockwatch demo`) send: the input motion resampled to the replay rate by linear
// interpolation, with the sensor model applied and the dropouts drawn, all before the first message goes out, so the
// paced loop only encodes and sends, and --samples-out, --log and the demo's offline run see the very same values.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "rockwatch/sim/analysis.hpp"

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

// Longest stream prepared in memory (about 14 h at 1 kHz): a typo such as --rate 1e4 on an hour-long record should
// be a message, not an exhausted machine.
inline constexpr std::size_t kMaxReplaySamples = 50'000'000;

struct ReplayStream {
  double rate_hz = 0.0;
  double source_dt_s = 0.0;     // the record's sample interval
  bool resampled = false;       // 1/rate differs from the record's dt
  bool has_vertical = false;    // v̈ from the record; else vg_mps2 is all zero (no vertical sensor)
  std::vector<double> ug_mps2;  // the values sent for seq i [m/s²], sensor model applied
  std::vector<double> vg_mps2;
  std::vector<std::uint8_t> sent;  // 1 = sent, 0 = dropped (--dropout)
  std::size_t dropped = 0;

  std::size_t size() const { return ug_mps2.size(); }
  double time_s(std::size_t i) const { return static_cast<double>(i) / rate_hz; }
  double duration_s() const { return size() == 0 ? 0.0 : time_s(size() - 1); }
};

// Resamples `motion` to `rate_hz` (sample i at t = i/rate, i = 0 .. floor(duration·rate); linear interpolation, bit for
// bit where 1/rate is the record's dt) and applies `sensor`. Throws UsageError when the stream would exceed
// kMaxReplaySamples.
ReplayStream make_replay_stream(const sim::GroundMotion& motion, double rate_hz, const SensorModel& sensor);

// The samples as sent, one row per seq i < count: "t_s,ug_mps2,vg_mps2" with '#' comments first ("# units: mps2",
// the rate). Values are written in the shortest form that reads back as the same double. A dropped sample's row
// holds the values of the last sample sent before it (0 before any), which is what the monitor holds while it
// bridges a short gap, and ends in "# dropped".
void write_samples_csv(std::ostream& out, const ReplayStream& stream, std::size_t count);

// The ground motion of the first `count` samples as the monitor runs them (dt = 1/rate; a dropped sample holds the
// previous one's values, as in write_samples_csv): the demo's offline input.
sim::GroundMotion stream_motion(const ReplayStream& stream, std::size_t count);

// The sample period in whole microseconds that --batch needs (ground_accel_batch_t::sample_period_us), or nullopt
// when 1/rate is not a whole number of microseconds.
std::optional<std::int32_t> whole_period_us(double rate_hz);

}  // namespace rockwatch::cli
