#include "rockwatch/sim/intensity_measures.hpp"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/measure_error.hpp"

namespace rockwatch::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

void check_samples(const char* what, const std::vector<double>& ag_mps2, double dt_s) {
  if (ag_mps2.empty()) throw MeasureError(std::string(what) + ": the record has no samples");
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) {
    throw MeasureError(std::string(what) + ": sample interval must be a finite value > 0 s (got " + number(dt_s) + ")");
  }
  for (std::size_t k = 0; k < ag_mps2.size(); ++k) {
    if (!std::isfinite(ag_mps2[k])) throw MeasureError(std::string(what) + ": sample " + std::to_string(k) + " is not finite");
  }
}

void check_gravity(double g_mps2) {
  if (!(std::isfinite(g_mps2) && g_mps2 > 0.0)) {
    throw MeasureError("intensity measures: g must be a finite value > 0 m/s2 (got " + number(g_mps2) + ")");
  }
}

// Cumulative trapezoidal integral from 0 at the first sample.
std::vector<double> integrate(const std::vector<double>& f, double dt_s) {
  std::vector<double> out(f.size(), 0.0);
  for (std::size_t k = 1; k < f.size(); ++k) out[k] = out[k - 1] + 0.5 * dt_s * (f[k - 1] + f[k]);
  return out;
}

// ∫ a² dt at every sample (trapezoidal rule on a²).
std::vector<double> cumulative_energy(const std::vector<double>& a, double dt_s) {
  std::vector<double> out(a.size(), 0.0);
  for (std::size_t k = 1; k < a.size(); ++k) out[k] = out[k - 1] + 0.5 * dt_s * (a[k - 1] * a[k - 1] + a[k] * a[k]);
  return out;
}

}  // namespace

BaselineCorrectedMotion baseline_corrected_motion(const std::vector<double>& ag_mps2, double dt_s) {
  check_samples("baseline correction", ag_mps2, dt_s);
  BaselineCorrectedMotion m;
  m.acc_mps2 = ag_mps2;
  const std::size_t n = ag_mps2.size();

  // 1. First integration.
  m.vel_mps = integrate(m.acc_mps2, dt_s);
  m.disp_m = integrate(m.vel_mps, dt_s);
  if (n < 4) return m;

  // 2. d ≈ p2 τ² + p3 τ³ with τ = t/L in [0, 1], so the normal equations stay well conditioned for any length.
  const double length_s = dt_s * static_cast<double>(n - 1);
  double s4 = 0.0, s5 = 0.0, s6 = 0.0, r2 = 0.0, r3 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double tau = static_cast<double>(k) / static_cast<double>(n - 1);
    const double tau2 = tau * tau;
    const double tau3 = tau2 * tau;
    s4 += tau2 * tau2;
    s5 += tau2 * tau3;
    s6 += tau3 * tau3;
    r2 += m.disp_m[k] * tau2;
    r3 += m.disp_m[k] * tau3;
  }
  const double det = s4 * s6 - s5 * s5;
  if (!(det > 0.0)) return m;
  const double p2 = (r2 * s6 - r3 * s5) / det;
  const double p3 = (s4 * r3 - s5 * r2) / det;
  m.c2_mps2 = p2 / (length_s * length_s);
  m.c3_mps3 = p3 / (length_s * length_s * length_s);

  // 3. Subtract the fit's second derivative and integrate again.
  for (std::size_t k = 0; k < n; ++k) {
    const double t_s = dt_s * static_cast<double>(k);
    m.acc_mps2[k] -= 2.0 * m.c2_mps2 + 6.0 * m.c3_mps3 * t_s;
  }
  m.vel_mps = integrate(m.acc_mps2, dt_s);
  m.disp_m = integrate(m.vel_mps, dt_s);
  return m;
}

double arias_intensity_mps(const std::vector<double>& ag_mps2, double dt_s, double g_mps2) {
  check_samples("Arias intensity", ag_mps2, dt_s);
  check_gravity(g_mps2);
  return kPi / (2.0 * g_mps2) * cumulative_energy(ag_mps2, dt_s).back();
}

std::vector<double> husid_curve(const std::vector<double>& ag_mps2, double dt_s) {
  check_samples("Husid curve", ag_mps2, dt_s);
  std::vector<double> h = cumulative_energy(ag_mps2, dt_s);
  const double total = h.back();
  if (!(total > 0.0)) return std::vector<double>(h.size(), 0.0);
  for (double& x : h) x /= total;
  h.back() = 1.0;  // exactly, so a fraction of 1 is always reached
  return h;
}

std::optional<double> husid_time_s(const std::vector<double>& husid, double dt_s, double fraction) {
  if (!(fraction > 0.0 && fraction <= 1.0)) {
    throw MeasureError("Husid crossing: the fraction must be in (0, 1] (got " + number(fraction) + ")");
  }
  if (husid.empty() || !(husid.back() > 0.0)) return std::nullopt;
  for (std::size_t k = 1; k < husid.size(); ++k) {
    if (husid[k] < fraction) continue;
    const double rise = husid[k] - husid[k - 1];
    const double within = rise > 0.0 ? (fraction - husid[k - 1]) / rise : 1.0;
    return dt_s * (static_cast<double>(k - 1) + within);
  }
  return std::nullopt;
}

IntensityMeasures intensity_measures(const std::vector<double>& ag_mps2, double dt_s, double g_mps2) {
  check_samples("intensity measures", ag_mps2, dt_s);
  check_gravity(g_mps2);
  IntensityMeasures im;
  im.pga_mps2 = peak_abs(ag_mps2);
  const BaselineCorrectedMotion corrected = baseline_corrected_motion(ag_mps2, dt_s);
  im.pgv_mps = peak_abs(corrected.vel_mps);
  im.pgd_m = peak_abs(corrected.disp_m);
  im.arias_mps = arias_intensity_mps(ag_mps2, dt_s, g_mps2);
  const std::vector<double> husid = husid_curve(ag_mps2, dt_s);
  im.t5_s = husid_time_s(husid, dt_s, 0.05);
  im.t75_s = husid_time_s(husid, dt_s, 0.75);
  im.t95_s = husid_time_s(husid, dt_s, 0.95);
  if (im.t5_s && im.t75_s) im.d5_75_s = *im.t75_s - *im.t5_s;
  if (im.t5_s && im.t95_s) im.d5_95_s = *im.t95_s - *im.t5_s;
  return im;
}

}  // namespace rockwatch::sim
