// From a 3-axis accelerometer sample in the sensor's own frame to the model's two inputs (SPEC §1):
//   ü  horizontal out-of-plane ground acceleration; ü > 0 pushes the wall towards x < 0, i.e. ü is the ground's
//      acceleration along the wall's +x (the direction in which x, the mid-height displacement, is positive);
//   v̈  vertical ground acceleration, up positive.
// [ü, v̈]ᵀ = to_wall · a_sensor − bias. Row 0 of to_wall holds the direction cosines of the wall's +x axis in
// the sensor frame, row 1 those of the upward vertical; a mounting rotation, axis swap or sign flip is just
// another matrix, and a per-row gain correction may scale it.
//
// The bias is whatever the sensor reads with the ground at rest, mapped to the wall: zero for a stream that
// already has gravity removed (as records do); a DC-coupled accelerometer reads +g on an up-pointing axis
// (specific force), so for one the vertical bias is g = 9.81 m/s² — otherwise v̈ would carry a constant +g.
//
// Set-up (default_sensor_axes, sensor_axes_valid) runs once in double; cast_sensor_axes makes the per-sample
// copy in the engine's arithmetic, and wall_inputs is the per-sample mapping in that arithmetic.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point_eigen.hpp"

namespace rockwatch::core {

template <typename Scalar>
struct SensorAxes {
  // Row 0: ü, row 1: v̈; columns: sensor x, y, z. Dimensionless direction cosines (times any gain correction).
  Eigen::Matrix<Scalar, 2, 3> to_wall = Eigen::Matrix<Scalar, 2, 3>::Zero();
  // [ü, v̈] the sensor reports with the ground at rest [m/s²].
  Eigen::Matrix<Scalar, 2, 1> bias_mps2 = Eigen::Matrix<Scalar, 2, 1>::Zero();
};

// [ü, v̈] [m/s²] from one sensor sample [m/s², sensor frame].
// Scaling and overflow (Fixed): each row is a 3-term inner product with one rounding per product and
// saturating sums, so the result is within 3 half-resolutions of the exact mapping of the quantised inputs;
// it saturates (never wraps) beyond the format's range (Q7.24: ±128 m/s² ≈ ±13 g).
template <typename Scalar>
Eigen::Matrix<Scalar, 2, 1> wall_inputs(const SensorAxes<Scalar>& axes,
                                        const Eigen::Matrix<Scalar, 3, 1>& sensor_mps2) {
  return axes.to_wall * sensor_mps2 - axes.bias_mps2;
}

// The mounting the monitor assumes unless configured: sensor x along the wall's +x (so it reads ü), sensor z
// up (v̈), sensor y along the wall (no input to the model), gravity already removed (zero bias).
inline SensorAxes<double> default_sensor_axes() {
  SensorAxes<double> axes;
  axes.to_wall << 1.0, 0.0, 0.0,  //
      0.0, 0.0, 1.0;
  axes.bias_mps2.setZero();
  return axes;
}

// The mapping in the engine's arithmetic: a copy for double, each entry rounded to nearest (saturating) for Fixed.
// Scaling and overflow (Fixed): entries beyond the format's range saturate; sensor_axes_valid keeps the
// direction cosines within ±1.5, which every Q format with at least one integer bit holds.
template <typename Out>
SensorAxes<Out> cast_sensor_axes(const SensorAxes<double>& axes) {
  const auto to_out = [](double v) { return Out(v); };
  SensorAxes<Out> out;
  out.to_wall = axes.to_wall.unaryExpr(to_out);
  out.bias_mps2 = axes.bias_mps2.unaryExpr(to_out);
  return out;
}

// Largest accepted |direction cosine|: a unit direction has entries ≤ 1; the margin leaves room for a gain
// correction, while anything larger is a configuration mistake (and would not fit a Q1.30 format).
inline constexpr double kMaxSensorDirectionCosine = 1.5;
// A row whose Euclidean norm is below this maps every acceleration to (almost) nothing: no real mounting does
// that, so it is taken as a missing row. (Q7.24 would also round such entries to a handful of steps.)
inline constexpr double kMinSensorRowNorm = 1e-3;

// Initialisation-time check: every entry finite, |direction cosines| ≤ 1.5, neither row (almost) zero.
inline bool sensor_axes_valid(const SensorAxes<double>& axes) {
  for (int r = 0; r < 2; ++r) {
    double squared_norm = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double v = axes.to_wall(r, c);
      if (!std::isfinite(v) || std::fabs(v) > kMaxSensorDirectionCosine) return false;
      squared_norm += v * v;
    }
    if (!(squared_norm >= kMinSensorRowNorm * kMinSensorRowNorm)) return false;
    if (!std::isfinite(axes.bias_mps2(r))) return false;
  }
  return true;
}

}  // namespace rockwatch::core
