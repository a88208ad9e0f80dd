// Elastic response spectrum of a whole record: one core::ResponseOscillator per period, each run over every
// sample (input linear between samples, oscillator at rest at the first sample, peaks at the samples, nothing
// appended after the last sample). The recurrence is exact for that input at any T/dt, so short periods need no
// special treatment: PSA tends to the PGA as T → 0 (checked down to T = dt/100 in the tests).
#pragma once

#include <cstddef>
#include <vector>

#include "rockwatch/core/response_oscillator.hpp"
#include "rockwatch/sim/measure_error.hpp"

namespace rockwatch::sim {

inline constexpr double kDefaultSpectrumFromS = 0.02;
inline constexpr double kDefaultSpectrumToS = 4.0;
inline constexpr std::size_t kDefaultSpectrumPeriods = 100;

// n periods from from_s to to_s (both included), equally spaced in log T. Throws MeasureError unless
// 0 < from_s < to_s (finite) and n ≥ 2.
std::vector<double> log_spaced_periods(double from_s, double to_s, std::size_t n);

// 0.02–4 s, 100 periods.
std::vector<double> default_spectrum_periods();

struct ResponseSpectrum {
  double damping = core::kDefaultDampingRatio;  // ζ [-]
  std::vector<double> periods_s;
  std::vector<double> sd_m;        // spectral displacement max|u|
  std::vector<double> psv_mps;     // pseudo-spectral velocity ω·Sd
  std::vector<double> psa_mps2;    // pseudo-spectral acceleration ω²·Sd (what design spectra Se(T) compare with)
  std::vector<double> sa_abs_mps2; // peak absolute acceleration max|ü + a_g| (≈ PSA for small ζ)
};

// Throws MeasureError for an empty record, a non-finite sample, dt ≤ 0, a period ≤ 0 or non-finite, damping
// outside [0, 1) or a (period, dt) pair whose coefficients overflow.
ResponseSpectrum response_spectrum(const std::vector<double>& ag_mps2, double dt_s, const std::vector<double>& periods_s,
                                   double damping = core::kDefaultDampingRatio);

}  // namespace rockwatch::sim
