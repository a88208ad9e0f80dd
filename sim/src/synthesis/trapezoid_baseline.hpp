// Baseline correction for generated records that keeps their quiet lead and tail: a spectrally matched record
// integrates to a small residual velocity and displacement at its end, which would read as a drift (a record that
// ends moving) in the analysis after the record. Two correction pulses shaped like the record's envelope,
//   φ1(t) = e(t),  φ2(t) = e(t)·(t − t̄)   (t̄ the envelope's centroid),
// are subtracted with the amplitudes that make the final velocity and displacement exactly zero under the
// trapezoidal rule from rest (the integration sim::analyse and the intensity measures use). The pulses are
// smooth and as long as the strong motion, so they change the spectrum only at periods far beyond the band.
#pragma once

#include <cstddef>
#include <vector>

namespace rockwatch::sim::synthesis {

struct TrapezoidEnd {
  double velocity_mps = 0.0;  // v at the last sample, integrated from rest
  double displacement_m = 0.0;
};

// v and d at the last sample by the trapezoidal rule from v = d = 0 at the first sample.
TrapezoidEnd trapezoid_end(const std::vector<double>& acc_mps2, double dt_s);

class TrapezoidBaseline {
 public:
  // Throws GeneratorError when the envelope gives a singular system (an all-zero or one-sample envelope).
  TrapezoidBaseline(const std::vector<double>& envelope, double dt_s);
  // Subtracts α·φ1 + β·φ2 from `acc_mps2` (same length as the envelope).
  void correct(std::vector<double>& acc_mps2, double dt_s) const;

 private:
  std::vector<double> phi1_, phi2_;
  double inverse_[2][2]{};  // inverse of [[v(φ1), v(φ2)], [d(φ1), d(φ2)]]
};

}  // namespace rockwatch::sim::synthesis
