#include "rockwatch/sim/response_spectrum.hpp"

#include <cmath>
#include <cstdio>
#include <cstddef>
#include <string>
#include <vector>

#include "rockwatch/core/response_oscillator.hpp"
#include "rockwatch/sim/measure_error.hpp"

namespace rockwatch::sim {

namespace {

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

void check_samples(const std::vector<double>& ag_mps2, double dt_s) {
  if (ag_mps2.empty()) throw MeasureError("response spectrum: the record has no samples");
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) {
    throw MeasureError("response spectrum: sample interval must be a finite value > 0 s (got " + number(dt_s) + ")");
  }
  for (std::size_t k = 0; k < ag_mps2.size(); ++k) {
    if (!std::isfinite(ag_mps2[k])) {
      throw MeasureError("response spectrum: sample " + std::to_string(k) + " is not finite");
    }
  }
}

}  // namespace

std::vector<double> log_spaced_periods(double from_s, double to_s, std::size_t n) {
  if (!(std::isfinite(from_s) && from_s > 0.0)) {
    throw MeasureError("periods: the first period must be a finite value > 0 s (got " + number(from_s) + ")");
  }
  if (!(std::isfinite(to_s) && to_s > from_s)) {
    throw MeasureError("periods: the last period must be finite and > the first (got " + number(from_s) + " to " +
                       number(to_s) + ")");
  }
  if (n < 2) throw MeasureError("periods: at least 2 periods are needed (got " + std::to_string(n) + ")");
  std::vector<double> periods(n);
  const double log_from = std::log(from_s);
  const double step = (std::log(to_s) - log_from) / static_cast<double>(n - 1);
  for (std::size_t i = 0; i < n; ++i) periods[i] = std::exp(log_from + step * static_cast<double>(i));
  // The ends exactly as asked, so "0.02:4:100" lists 0.02 and 4, not 0.019999999999999997.
  periods.front() = from_s;
  periods.back() = to_s;
  return periods;
}

std::vector<double> default_spectrum_periods() {
  return log_spaced_periods(kDefaultSpectrumFromS, kDefaultSpectrumToS, kDefaultSpectrumPeriods);
}

ResponseSpectrum response_spectrum(const std::vector<double>& ag_mps2, double dt_s, const std::vector<double>& periods_s,
                                   double damping) {
  check_samples(ag_mps2, dt_s);
  // Checked here too, so an empty period list does not hide a bad damping value.
  if (!(std::isfinite(damping) && damping >= 0.0 && damping < 1.0)) {
    throw MeasureError("response spectrum: damping ratio must be in [0, 1) (got " + number(damping) + ")");
  }
  ResponseSpectrum s;
  s.damping = damping;
  s.periods_s = periods_s;
  const std::size_t n = periods_s.size();
  s.sd_m.resize(n);
  s.psv_mps.resize(n);
  s.psa_mps2.resize(n);
  s.sa_abs_mps2.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    core::ResponseOscillator osc;
    const core::OscillatorStatus status = osc.init(periods_s[i], damping, dt_s);
    if (status != core::OscillatorStatus::ok) {
      throw MeasureError("response spectrum: period " + number(periods_s[i]) + " s, damping " + number(damping) +
                         ", dt " + number(dt_s) + " s: " + core::oscillator_status_text(status));
    }
    osc.reset(ag_mps2.front());
    for (std::size_t k = 1; k < ag_mps2.size(); ++k) osc.step(ag_mps2[k]);
    s.sd_m[i] = osc.sd_m();
    s.psv_mps[i] = osc.psv_mps();
    s.psa_mps2[i] = osc.psa_mps2();
    s.sa_abs_mps2[i] = osc.max_abs_acceleration_mps2();
  }
  return s;
}

}  // namespace rockwatch::sim
