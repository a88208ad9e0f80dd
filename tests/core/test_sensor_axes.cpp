// Sensor frame → model inputs: the default mounting, a rotated mounting (double and Q7.24), gravity bias, sign
// convention, casting and validation.
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point_eigen.hpp"
#include "rockwatch/core/sensor_axes.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch::core;

namespace {

using Q = Fixed<7, 24>;
constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

// Sensor mounted rotated by `deg` about the wall's y axis (along the wall): the columns of R are the sensor's
// axes in the wall frame (x out of plane, y along the wall, z up). A wall-frame vector w reads s = Rᵀw.
Eigen::Matrix3d rotation_about_y(double deg) {
  const double a = deg * kPi / 180.0;
  Eigen::Matrix3d r;
  r << std::cos(a), 0.0, std::sin(a),  //
      0.0, 1.0, 0.0,                    //
      -std::sin(a), 0.0, std::cos(a);
  return r;
}

// The mapping for that mounting: rows x and z of R (direction cosines of the wall's +x and up in the sensor
// frame).
SensorAxes<double> axes_for(const Eigen::Matrix3d& r, double vertical_bias_mps2) {
  SensorAxes<double> axes;
  axes.to_wall.row(0) = r.row(0);
  axes.to_wall.row(1) = r.row(2);
  axes.bias_mps2 << 0.0, vertical_bias_mps2;
  return axes;
}

// Ground motions in the wall frame (ü, along-wall, v̈) [m/s²], including the along-wall component the model
// ignores.
const Eigen::Vector3d kGroundMotions[] = {{1.0, 0.0, 0.0},   {0.0, 0.0, 1.0},  {2.5, -1.0, -0.7},
                                          {-3.2, 4.0, 1.1},  {-9.0, 0.3, 5.5}, {0.01, -0.02, 0.03},
                                          {12.0, 8.0, -7.5}, {0.0, 3.0, 0.0}};

Eigen::Matrix<Q, 3, 1> to_fixed(const Eigen::Vector3d& v) {
  return v.unaryExpr([](double x) { return Q(x); });
}

}  // namespace

TEST_GROUP(SensorAxes){};

TEST(SensorAxes, DefaultMountingReadsXAsHorizontalAndZAsVertical) {
  const SensorAxes<double> axes = default_sensor_axes();
  CHECK(sensor_axes_valid(axes));
  const Eigen::Vector2d in = wall_inputs(axes, Eigen::Vector3d(1.5, -7.0, -0.25));
  DOUBLES_EQUAL(1.5, in(0), 0.0);
  DOUBLES_EQUAL(-0.25, in(1), 0.0);
  CHECK(axes.bias_mps2.isZero(0.0));
}

TEST(SensorAxes, SignConventionFollowsTheWallsPlusX) {
  // ü is the ground's acceleration along the wall's +x (ü > 0 pushes the wall towards x < 0). A sensor mounted
  // turned 180° about the vertical has its x along the wall's −x: it reads −ü, and the mapping restores ü.
  SensorAxes<double> axes = default_sensor_axes();
  axes.to_wall(0, 0) = -1.0;
  CHECK(sensor_axes_valid(axes));
  DOUBLES_EQUAL(2.0, wall_inputs(axes, Eigen::Vector3d(-2.0, 0.0, 0.0))(0), 0.0);
  // Mounted upside down: z reads −v̈.
  axes.to_wall(1, 2) = -1.0;
  DOUBLES_EQUAL(-0.5, wall_inputs(axes, Eigen::Vector3d(0.0, 0.0, 0.5))(1), 0.0);
}

TEST(SensorAxes, RotatedSensorRecoversBothInputsInDouble) {
  for (const double deg : {30.0, -30.0, 45.0, 90.0, 180.0}) {
    const Eigen::Matrix3d r = rotation_about_y(deg);
    const SensorAxes<double> axes = axes_for(r, 0.0);
    CHECK(sensor_axes_valid(axes));
    for (const Eigen::Vector3d& w : kGroundMotions) {
      const Eigen::Vector3d sensor = r.transpose() * w;
      const Eigen::Vector2d in = wall_inputs(axes, sensor);
      DOUBLES_EQUAL(w(0), in(0), 1e-12);
      DOUBLES_EQUAL(w(2), in(1), 1e-12);
    }
  }
}

TEST(SensorAxes, GravityOnADcCoupledSensorIsRemovedByTheBias) {
  // At 30°, a DC-coupled sensor reads the specific force a + g·up; the bias g on the vertical removes it.
  const Eigen::Matrix3d r = rotation_about_y(30.0);
  const SensorAxes<double> axes = axes_for(r, kG);
  CHECK(sensor_axes_valid(axes));
  for (const Eigen::Vector3d& w : kGroundMotions) {
    const Eigen::Vector3d sensor = r.transpose() * (w + Eigen::Vector3d(0.0, 0.0, kG));
    const Eigen::Vector2d in = wall_inputs(axes, sensor);
    DOUBLES_EQUAL(w(0), in(0), 1e-12);
    DOUBLES_EQUAL(w(2), in(1), 1e-12);
  }
}

TEST(SensorAxes, RotatedSensorRecoversBothInputsInQ7_24) {
  for (const double bias : {0.0, kG}) {
    const Eigen::Matrix3d r = rotation_about_y(30.0);
    const SensorAxes<double> axes = axes_for(r, bias);
    const SensorAxes<Q> fixed_axes = cast_sensor_axes<Q>(axes);
    for (const Eigen::Vector3d& w : kGroundMotions) {
      const Eigen::Vector3d sensor = r.transpose() * (w + Eigen::Vector3d(0.0, 0.0, bias));
      const Eigen::Matrix<Q, 3, 1> sensor_q = to_fixed(sensor);
      const Eigen::Matrix<Q, 2, 1> in = wall_inputs(fixed_axes, sensor_q);
      // Error bound per row: quantisation of the cosines (½ step each, times |sensor|) and of the sensor values
      // (½ step each, times |cosine| ≤ 1), one rounding per product (½ step each), the bias' quantisation.
      const double half_step = 0.5 * Q::resolution_value();
      const double bound = half_step * (sensor.cwiseAbs().sum() + 3.0 + 3.0 + 1.0);
      DOUBLES_EQUAL(w(0), in(0).to_double(), bound);
      DOUBLES_EQUAL(w(2), in(1).to_double(), bound);
      CHECK(bound < 2e-6);
    }
  }
}

TEST(SensorAxes, CastRoundsEveryEntryIntoTheFormat) {
  const SensorAxes<double> axes = axes_for(rotation_about_y(30.0), kG);
  const SensorAxes<double> same = cast_sensor_axes<double>(axes);
  CHECK(same.to_wall == axes.to_wall);
  CHECK(same.bias_mps2 == axes.bias_mps2);
  const SensorAxes<Q> q = cast_sensor_axes<Q>(axes);
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 3; ++c) CHECK(q.to_wall(r, c) == Q(axes.to_wall(r, c)));
    CHECK(q.bias_mps2(r) == Q(axes.bias_mps2(r)));
  }
  // A default-constructed mapping is zero (not uninitialised), and maps everything to −bias = 0.
  const SensorAxes<Q> zero;
  CHECK(zero.to_wall == (Eigen::Matrix<Q, 2, 3>::Zero()));
  CHECK(zero.bias_mps2 == (Eigen::Matrix<Q, 2, 1>::Zero()));
}

TEST(SensorAxes, ValidationRejectsNonFiniteLargeAndZeroRows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const SensorAxes<double> good = axes_for(rotation_about_y(30.0), kG);
  CHECK(sensor_axes_valid(good));

  SensorAxes<double> a = good;
  a.to_wall(0, 1) = nan;
  CHECK_FALSE(sensor_axes_valid(a));
  a = good;
  a.to_wall(1, 2) = -inf;
  CHECK_FALSE(sensor_axes_valid(a));
  a = good;
  a.bias_mps2(1) = nan;
  CHECK_FALSE(sensor_axes_valid(a));
  a = good;
  a.bias_mps2(0) = inf;
  CHECK_FALSE(sensor_axes_valid(a));

  // |direction cosine| ≤ 1.5 (room for a gain correction).
  a = good;
  a.to_wall(0, 0) = 1.5;
  CHECK(sensor_axes_valid(a));
  a.to_wall(0, 0) = -1.5;
  CHECK(sensor_axes_valid(a));
  a.to_wall(0, 0) = 1.51;
  CHECK_FALSE(sensor_axes_valid(a));
  a.to_wall(0, 0) = -2.0;
  CHECK_FALSE(sensor_axes_valid(a));

  // A zero (or negligible) row: the input would vanish.
  a = good;
  a.to_wall.row(0).setZero();
  CHECK_FALSE(sensor_axes_valid(a));
  a = good;
  a.to_wall.row(1) << 1e-4, 0.0, -1e-4;
  CHECK_FALSE(sensor_axes_valid(a));
  CHECK_FALSE(sensor_axes_valid(SensorAxes<double>{}));
}
