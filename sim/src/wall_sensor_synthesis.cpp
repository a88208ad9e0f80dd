#include "rockwatch/sim/wall_sensor_synthesis.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "rockwatch/sim/synthesis/random_stream.hpp"

namespace rockwatch::sim {

namespace {

std::string text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void require(bool ok, const std::string& what) {
  if (!ok) throw SensorModelError("sensor model: " + what);
}

// The true response at time t, linear between the history rows around it (rows ascending in t).
struct TrueResponse {
  double x_m, a_mid_mps2;
};

class HistoryCursor {
 public:
  HistoryCursor(const std::vector<HistoryRow>& rows, double g_mps2, double h1_m) : rows_(rows), g_(g_mps2), h1_(h1_m) {}

  TrueResponse at(double t_s) {
    while (i_ + 1 < rows_.size() && rows_[i_ + 1].t_s < t_s) ++i_;
    const HistoryRow& a = rows_[i_];
    if (i_ + 1 >= rows_.size() || t_s <= a.t_s) return of(a, a, 0.0);
    const HistoryRow& b = rows_[i_ + 1];
    const double span = b.t_s - a.t_s;
    const double f = span > 0.0 ? (t_s - a.t_s) / span : 1.0;
    return of(a, b, f);
  }

 private:
  TrueResponse of(const HistoryRow& a, const HistoryRow& b, double f) const {
    const auto lerp = [f](double u, double v) { return u + (v - u) * f; };
    const double x = lerp(a.x_m, b.x_m);
    const double gravity = g_ + lerp(a.vg_mps2, b.vg_mps2);
    // SPEC §8: the absolute horizontal acceleration of the hinge on block 1.
    const double a_mid = lerp(a.ug_mps2, b.ug_mps2) + lerp(a.xdd_mps2, b.xdd_mps2) - gravity * x / h1_;
    return TrueResponse{x, a_mid};
  }

  const std::vector<HistoryRow>& rows_;
  double g_, h1_;
  std::size_t i_ = 0;
};

}  // namespace

void check_sensor_model(const SensorModel& m) {
  require(std::isfinite(m.rate_hz) && m.rate_hz >= 0.0 && m.rate_hz <= 1e5,
          "rate must be in (0, 100000] Hz, or 0 for the record's rate (got " + text(m.rate_hz) + ")");
  require(std::isfinite(m.x_noise_m) && m.x_noise_m >= 0.0 && m.x_noise_m <= 1.0,
          "displacement noise must be in [0, 1] m (got " + text(m.x_noise_m) + ")");
  require(std::isfinite(m.x_bias_m) && std::fabs(m.x_bias_m) <= 1.0,
          "displacement bias must be in [-1, 1] m (got " + text(m.x_bias_m) + ")");
  require(std::isfinite(m.x_quantum_m) && m.x_quantum_m >= 0.0 && m.x_quantum_m <= 1.0,
          "displacement quantum must be in [0, 1] m (got " + text(m.x_quantum_m) + ")");
  if (m.a_noise_mps2) {
    require(std::isfinite(*m.a_noise_mps2) && *m.a_noise_mps2 >= 0.0 && *m.a_noise_mps2 <= 1000.0,
            "acceleration noise must be in [0, 1000] m/s2 (got " + text(*m.a_noise_mps2) + ")");
  }
  for (const SensorDropout& d : m.dropouts) {
    require(std::isfinite(d.from_s) && std::isfinite(d.to_s) && d.from_s < d.to_s,
            "a dropout window must be finite with from < to (got " + text(d.from_s) + ":" + text(d.to_s) + ")");
  }
}

std::vector<core::WallSensorSample> synthesize_wall_sensors(const core::WallParameters& wall,
                                                            const AnalysisResult& truth, double record_dt_s,
                                                            const SensorModel& m) {
  check_sensor_model(m);
  if (truth.history.empty()) throw AnalysisError("sensor synthesis needs the analysis history (keep_history)");
  if (!(std::isfinite(record_dt_s) && record_dt_s > 0.0)) throw AnalysisError("record dt must be > 0 s");
  const double period_s = m.rate_hz > 0.0 ? 1.0 / m.rate_hz : record_dt_s;
  const double t_last = truth.history.back().t_s;
  const auto n = static_cast<std::size_t>(std::floor(t_last / period_s + 1e-9)) + 1;

  synthesis::RandomStream noise(m.seed);
  HistoryCursor truth_at(truth.history, wall.g_mps2, wall.h1_m);
  std::vector<core::WallSensorSample> samples;
  samples.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t_s = double(k) * period_s;
    const TrueResponse r = truth_at.at(t_s);
    double x = r.x_m + m.x_bias_m + m.x_noise_m * noise.normal();
    if (m.x_quantum_m > 0.0) x = std::round(x / m.x_quantum_m) * m.x_quantum_m;
    double a = 0.0;
    if (m.a_noise_mps2) a = r.a_mid_mps2 + *m.a_noise_mps2 * noise.normal();
    bool dropped = false;
    for (const SensorDropout& d : m.dropouts) dropped = dropped || (t_s >= d.from_s && t_s < d.to_s);
    if (dropped) continue;
    core::WallSensorSample s;
    s.utime_us = static_cast<std::int64_t>(std::llround(t_s * 1e6));
    s.x_mid_m = x;
    s.x_valid = true;
    s.a_mid_mps2 = a;
    s.a_valid = m.a_noise_mps2.has_value();
    samples.push_back(s);
  }
  return samples;
}

}  // namespace rockwatch::sim
