// Velocity and displacement of a ground motion by the trapezoidal rule from rest, written out for the tests of
// generated records rather than borrowed from the generator they check.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace rockwatch::test {

struct TrapezoidState {
  double v_mps = 0.0;        // velocity at the last sample
  double d_m = 0.0;          // displacement at the last sample
  double max_abs_d_m = 0.0;  // largest |d| on the way
};

inline TrapezoidState trapezoid_from_rest(const std::vector<double>& a_mps2, double dt_s) {
  TrapezoidState e;
  for (std::size_t k = 1; k < a_mps2.size(); ++k) {
    const double v_next = e.v_mps + 0.5 * dt_s * (a_mps2[k - 1] + a_mps2[k]);
    e.d_m += 0.5 * dt_s * (e.v_mps + v_next);
    e.v_mps = v_next;
    e.max_abs_d_m = std::max(e.max_abs_d_m, std::abs(e.d_m));
  }
  return e;
}

}  // namespace rockwatch::test
