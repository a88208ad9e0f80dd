#include "trapezoid_baseline.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"

namespace rockwatch::sim::synthesis {

TrapezoidEnd trapezoid_end(const std::vector<double>& a, double dt_s) {
  TrapezoidEnd end;
  double v = 0.0;
  double d = 0.0;
  for (std::size_t k = 1; k < a.size(); ++k) {
    const double v_next = v + 0.5 * dt_s * (a[k - 1] + a[k]);
    d += 0.5 * dt_s * (v + v_next);
    v = v_next;
  }
  end.velocity_mps = v;
  end.displacement_m = d;
  return end;
}

TrapezoidBaseline::TrapezoidBaseline(const std::vector<double>& envelope, double dt_s)
    : phi1_(envelope), phi2_(envelope.size()) {
  double weight = 0.0;
  double moment = 0.0;
  for (std::size_t k = 0; k < envelope.size(); ++k) {
    weight += envelope[k];
    moment += envelope[k] * static_cast<double>(k) * dt_s;
  }
  const double centroid_s = weight > 0.0 ? moment / weight : 0.0;
  for (std::size_t k = 0; k < envelope.size(); ++k) {
    phi2_[k] = envelope[k] * (static_cast<double>(k) * dt_s - centroid_s);
  }
  const TrapezoidEnd e1 = trapezoid_end(phi1_, dt_s);
  const TrapezoidEnd e2 = trapezoid_end(phi2_, dt_s);
  const double det = e1.velocity_mps * e2.displacement_m - e2.velocity_mps * e1.displacement_m;
  const double scale = std::abs(e1.velocity_mps * e2.displacement_m) + std::abs(e2.velocity_mps * e1.displacement_m);
  if (!(std::abs(det) > 1e-12 * scale) || !(scale > 0.0)) {
    throw GeneratorError("baseline correction: the envelope gives no independent correction pulses");
  }
  inverse_[0][0] = e2.displacement_m / det;
  inverse_[0][1] = -e2.velocity_mps / det;
  inverse_[1][0] = -e1.displacement_m / det;
  inverse_[1][1] = e1.velocity_mps / det;
}

void TrapezoidBaseline::correct(std::vector<double>& a, double dt_s) const {
  const TrapezoidEnd end = trapezoid_end(a, dt_s);
  const double alpha = inverse_[0][0] * end.velocity_mps + inverse_[0][1] * end.displacement_m;
  const double beta = inverse_[1][0] * end.velocity_mps + inverse_[1][1] * end.displacement_m;
  for (std::size_t k = 0; k < a.size(); ++k) a[k] -= alpha * phi1_[k] + beta * phi2_[k];
}

}  // namespace rockwatch::sim::synthesis
