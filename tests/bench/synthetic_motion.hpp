// Deterministic, earthquake-like ground motion for the benchmarks: no record files, the same samples on every
// run (own LCG for the phases: <random> distributions differ between standard libraries).
//
// Stationary part: a sum of harmonics of 1/40 Hz between 1.5 and 15 Hz with Kanai–Tajimi amplitudes
// (firm soil, f_g = 4 Hz, ζ_g = 0.6). Harmonics of the 40 s period make the signal exactly periodic, so the
// stepper benchmarks can replay it in a loop without a jump in the input at the seam.
// Record: the stationary part under a Jennings-type envelope (2 s build-up, 10 s strong phase, decay), so the
// wall starts from rest, rocks with many impacts and settles, like under a real record.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::bench {

inline constexpr double kG = 9.81;                 // [m/s²], as in core::paper_wall()
inline constexpr double kDt = 0.005;               // 200 Hz, the monitor's sample rate [s]
inline constexpr std::size_t kPeriodSamples = 8000;  // 40 s at 200 Hz
inline constexpr double kPeriodS = kDt * double(kPeriodSamples);

// Shape of the motion only; each consumer scales it to the peak acceleration it needs.
inline std::vector<double> stationary_unscaled() {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double f_g = 4.0, zeta_g = 0.6;
  // 1.5 Hz .. 15 Hz in steps of 1/40 Hz. The band starts at 1.5 Hz on purpose: with content down to 0.5 Hz the
  // slender paper wall (b = 0.10 m, 3.5 m tall) collapses at 0.2 g, and with content down to 1 Hz the outcome
  // flips between safe and collapse with small changes of PGA. From 1.5 Hz it does not collapse anywhere from
  // 0.15 g to 0.3 g, so the benchmark measures rocking, not a stopped stepper.
  constexpr int k_min = 60, k_max = 600;
  std::uint64_t lcg = 0x243F6A8885A308D3ULL;  // fixed seed: the benchmark input must never change silently
  std::vector<double> amplitude, omega, phase;
  for (int k = k_min; k <= k_max; ++k) {
    const double f = double(k) / kPeriodS;
    const double r2 = (f / f_g) * (f / f_g);
    const double kt = (1.0 + 4.0 * zeta_g * zeta_g * r2) / ((1.0 - r2) * (1.0 - r2) + 4.0 * zeta_g * zeta_g * r2);
    lcg = lcg * 6364136223846793005ULL + 1442695040888963407ULL;
    amplitude.push_back(std::sqrt(kt));
    omega.push_back(2.0 * kPi * f);
    phase.push_back(2.0 * kPi * double(lcg >> 11) / 9007199254740992.0);  // top 53 bits -> [0, 1)
  }
  std::vector<double> a(kPeriodSamples, 0.0);
  for (std::size_t n = 0; n < kPeriodSamples; ++n) {
    const double t = double(n) * kDt;
    double sum = 0.0;
    for (std::size_t c = 0; c < amplitude.size(); ++c) sum += amplitude[c] * std::sin(omega[c] * t + phase[c]);
    a[n] = sum;
  }
  return a;
}

inline void scale_to_peak(std::vector<double>& a, double peak_mps2) {
  const double peak = sim::peak_abs(a);
  for (double& v : a) v *= peak_mps2 / peak;
}

// One 40 s period (8000 samples; sample 8000 would equal sample 0) for looped replay.
inline std::vector<double> stationary_motion(double peak_mps2) {
  std::vector<double> a = stationary_unscaled();
  scale_to_peak(a, peak_mps2);
  return a;
}

inline double envelope(double t_s) {
  if (t_s < 2.0) return (t_s / 2.0) * (t_s / 2.0);
  if (t_s < 12.0) return 1.0;
  return std::exp(-0.25 * (t_s - 12.0));
}

// A 40 s record at 200 Hz, 8001 samples (both ends included), horizontal only, PGA = pga_mps2.
inline sim::GroundMotion earthquake_record(double pga_mps2) {
  const std::vector<double> s = stationary_unscaled();
  sim::GroundMotion m;
  m.dt_s = kDt;
  m.ug_mps2.resize(kPeriodSamples + 1);
  for (std::size_t n = 0; n <= kPeriodSamples; ++n) {
    m.ug_mps2[n] = envelope(double(n) * kDt) * s[n % kPeriodSamples];
  }
  scale_to_peak(m.ug_mps2, pga_mps2);
  return m;
}

}  // namespace rockwatch::bench
