#include "common/replay_out/replay_stream.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "common/records_in/align.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/sim/synthesis/random_stream.hpp"

namespace rockwatch::cli {

namespace {

// The dropout draws have a stream of their own, so adding noise never changes which samples are dropped.
constexpr std::uint64_t kDropoutStreamOffset = 0x9E3779B97F4A7C15ULL;

double sensor_value(double a, const SensorModel& s, sim::synthesis::RandomStream& noise) {
  double v = a + s.bias_mps2;
  if (s.noise_sd_mps2 > 0.0) v += s.noise_sd_mps2 * noise.normal();
  if (s.quantum_mps2 > 0.0) v = s.quantum_mps2 * std::nearbyint(v / s.quantum_mps2);
  return v;
}

}  // namespace

ReplayStream make_replay_stream(const sim::GroundMotion& motion, double rate_hz, const SensorModel& sensor) {
  ReplayStream s;
  s.rate_hz = rate_hz;
  s.source_dt_s = motion.dt_s;
  s.has_vertical = !motion.vg_mps2.empty();
  const double samples = std::floor(motion.duration_s() * rate_hz + 1e-6) + 1.0;
  if (samples > static_cast<double>(kMaxReplaySamples)) {
    throw UsageError("--rate " + number_text(rate_hz) + " Hz over " + number_text(motion.duration_s()) + " s is " +
                     number_text(samples) + " samples, more than the " + std::to_string(kMaxReplaySamples) +
                     " a replay may hold: lower --rate or shorten the record");
  }
  const TimeGrid source{0.0, motion.dt_s, motion.ug_mps2.size()};
  const TimeGrid target{0.0, 1.0 / rate_hz, static_cast<std::size_t>(samples)};
  s.resampled = std::fabs(target.dt_s - source.dt_s) > 1e-9 * source.dt_s;
  s.ug_mps2 = resample_linear(motion.ug_mps2, source, target);
  s.vg_mps2 = s.has_vertical ? resample_linear(motion.vg_mps2, source, target) : std::vector<double>(target.count, 0.0);
  s.sent.assign(target.count, 1);

  if (sensor.bias_mps2 != 0.0 || sensor.noise_sd_mps2 > 0.0 || sensor.quantum_mps2 > 0.0) {
    sim::synthesis::RandomStream noise(sensor.seed);
    for (std::size_t i = 0; i < target.count; ++i) {
      s.ug_mps2[i] = sensor_value(s.ug_mps2[i], sensor, noise);
      if (s.has_vertical) s.vg_mps2[i] = sensor_value(s.vg_mps2[i], sensor, noise);
    }
  }
  if (sensor.dropout > 0.0) {
    sim::synthesis::RandomStream draws(sensor.seed + kDropoutStreamOffset);
    for (std::size_t i = 0; i < target.count; ++i) {
      if (draws.uniform() < sensor.dropout) {
        s.sent[i] = 0;
        ++s.dropped;
      }
    }
  }
  return s;
}

void write_samples_csv(std::ostream& out, const ReplayStream& s, std::size_t count) {
  out << "# rockwatch replay: the samples as sent; row i is seq i\n"
         "# units: mps2\n"
         "# rate_hz: "
      << number_text(s.rate_hz)
      << "\n"
         "# a row ending in '# dropped' was not sent (--dropout): it holds the last values sent, as the monitor\n"
         "# bridges a short gap\n"
         "t_s,ug_mps2,vg_mps2\n";
  double held_ug = 0.0, held_vg = 0.0;
  for (std::size_t i = 0; i < count && i < s.size(); ++i) {
    if (s.sent[i]) {
      held_ug = s.ug_mps2[i];
      held_vg = s.vg_mps2[i];
    }
    out << number_text(s.time_s(i)) << ',' << number_text(held_ug) << ',' << number_text(held_vg);
    if (!s.sent[i]) out << "  # dropped";
    out << '\n';
  }
}

sim::GroundMotion stream_motion(const ReplayStream& s, std::size_t count) {
  sim::GroundMotion m;
  m.dt_s = 1.0 / s.rate_hz;
  double held_ug = 0.0, held_vg = 0.0;
  for (std::size_t i = 0; i < count && i < s.size(); ++i) {
    if (s.sent[i]) {
      held_ug = s.ug_mps2[i];
      held_vg = s.vg_mps2[i];
    }
    m.ug_mps2.push_back(held_ug);
    if (s.has_vertical) m.vg_mps2.push_back(held_vg);
  }
  return m;
}

std::optional<std::int32_t> whole_period_us(double rate_hz) {
  const double period_us = 1e6 / rate_hz;
  const double whole = std::round(period_us);
  if (!(whole >= 1.0) || std::fabs(period_us - whole) > 1e-9 * period_us) return std::nullopt;
  return static_cast<std::int32_t>(whole);
}

}  // namespace rockwatch::cli
