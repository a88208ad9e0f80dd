// Ground-motion intensity measures of a whole record: PGA, PGV and PGD (after baseline correction), Arias
// intensity and the significant durations D5-75 and D5-95 from the normalised Arias (Husid) curve.
//
// PGA, Arias intensity and the durations use the record as given; only PGV and PGD use the baseline-corrected
// motion, because integration turns a small offset or drift in acceleration into a large one in displacement.
//
// Baseline correction (baseline_corrected_motion), in the manner of Ancheta et al. (2013) / USGS gmprocess but
// with a cubic instead of a 6th-order polynomial:
//   1. Velocity and displacement by the trapezoidal rule from rest (v = d = 0 at the first sample).
//   2. A least-squares fit d(t) ≈ c2 t² + c3 t³ over the whole record (no constant or linear term, so the start
//      from rest is kept); its second derivative 2 c2 + 6 c3 t is subtracted from the acceleration.
//   3. Velocity and displacement integrated again (trapezoidal rule) from the corrected acceleration.
// There is no separate pre-event mean removal: a constant offset c in acceleration integrates (exactly, by the
// trapezoidal rule) to c t²/2 in displacement, which the t² term of the fit removes exactly, so subtracting a
// mean first would not change the result. A linear drift in acceleration is removed the same way by the t³ term.
// Like every polynomial baseline correction this also removes a genuine permanent displacement (fling step).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "rockwatch/sim/measure_error.hpp"

namespace rockwatch::sim {

struct BaselineCorrectedMotion {
  std::vector<double> acc_mps2;   // corrected acceleration
  std::vector<double> vel_mps;    // its trapezoidal integral from rest
  std::vector<double> disp_m;     // and the integral of that
  double c2_mps2 = 0.0;                // fitted displacement c2 t² + c3 t³ [m/s², m/s³]
  double c3_mps3 = 0.0;
};

// Throws MeasureError for an empty record, a non-finite sample or dt ≤ 0. Records of fewer than 4 samples are
// only integrated (too short to fit).
BaselineCorrectedMotion baseline_corrected_motion(const std::vector<double>& ag_mps2, double dt_s);

// I_A = π/(2g) ∫ a² dt [m/s], the integral by the trapezoidal rule on a².
double arias_intensity_mps(const std::vector<double>& ag_mps2, double dt_s, double g_mps2);

// The Husid curve: ∫₀^t a² dt / ∫₀^T a² dt at every sample (trapezoidal rule), from 0 to 1. All zeros when the
// record has no energy.
std::vector<double> husid_curve(const std::vector<double>& ag_mps2, double dt_s);

// First time [s from the first sample] the Husid curve reaches `fraction` (0 < fraction ≤ 1), linearly
// interpolated between the two samples around the crossing; nullopt when the record has no energy.
std::optional<double> husid_time_s(const std::vector<double>& husid, double dt_s, double fraction);

struct IntensityMeasures {
  double pga_mps2 = 0.0;   // max |a| of the record as given
  double pgv_mps = 0.0;    // max |v| of the baseline-corrected motion
  double pgd_m = 0.0;      // max |d| of the baseline-corrected motion
  double arias_mps = 0.0;  // Arias intensity
  std::optional<double> t5_s, t75_s, t95_s;  // Husid crossing times (nullopt: no energy)
  std::optional<double> d5_75_s, d5_95_s;    // t75 − t5, t95 − t5 [s]
};

// Throws MeasureError for an empty record, a non-finite sample, dt ≤ 0 or g ≤ 0.
IntensityMeasures intensity_measures(const std::vector<double>& ag_mps2, double dt_s, double g_mps2);

}  // namespace rockwatch::sim
