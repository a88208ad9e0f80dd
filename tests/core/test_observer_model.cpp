// The observer's model as scripts/derive_observer.py derives it with SymPy (core/observer/generated/observer_model.hpp)
// against the stepper the observer corrects (core::RockingStepper<double>, linear model, ü = v̈ = 0): the Newmark step
// reproduces the stepper's, its Jacobian the stepper's finite differences (in x, ẋ, κc, κk), the saltation matrix
// the finite differences of a short step through an impact (in x, ẋ, √r), the accelerometer's H the finite
// differences of ü + ẍ − G·x/h1 read from the stepper. And the generated header is what the script writes now.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ci_skip.hpp"
#include "rockwatch/core/observer/generated/observer_model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/wall_observer.hpp"

#include <CppUTest/TestHarness.h>  // last: its leak detector redefines new

using namespace rockwatch::core;
namespace om = rockwatch::core::observer_model;

namespace {

StepperSetup<double> setup_dt(double dt_s, double r = 0.7) {
  StepperOptions o;
  o.dt_s = dt_s;
  return make_stepper_setup(paper_wall(), ModelKind::linear, r, o);
}

// The side's nominal k_s = p4/p1 and f_s = ẍ at the hinge (ü = 0, G = g), as WallObserver::init computes them.
struct SideConstants {
  double k_s, f_s;
};
SideConstants side_constants(const StepperSetup<double>& setup, Side side) {
  const ModelConstants<double>& c = setup.model;
  const int i = side_index(side);
  const double s = side == Side::positive ? 1.0 : -1.0;
  return {(c.c4_fp[i] + c.c4_g * setup.g_mps2) / c.c1, -s * (c.c6_fp[i] + c.c6_g * setup.g_mps2) / c.c1};
}

// The stepper's step from (x, ẋ) with the capacity scaled by (κc, κk) and √r = e: (x₁, ẋ₁), and whether it held an
// impact.
struct Stepped {
  double x1, xd1;
  int impacts;
};
Stepped stepper_step(const StepperSetup<double>& setup, double x, double xd, double kc, double kk, double e) {
  RockingStepper<double> s;
  s.init(setup);
  s.set_capacity_scales(kc, kk);
  s.set_sqrt_r(e);
  s.set_state(x, xd, 0.0, 0.0);
  const StepReport<double> r = s.step(0.0, 0.0);
  return {s.state().x_m, s.state().xd_mps, r.impacts_total};
}

void check_close(double expected, double actual, double rel, double abs_tol, const std::string& what) {
  const double tol = abs_tol + rel * std::fabs(expected);
  if (!(std::fabs(expected - actual) <= tol)) {
    char text[200];
    std::snprintf(text, sizeof text, "%s: expected %.9g, got %.9g (tolerance %.3g)", what.c_str(), expected, actual,
                  tol);
    FAIL(text);
  }
}

}  // namespace

TEST_GROUP(ObserverModel){};

TEST(ObserverModel, TheGeneratedNewmarkStepIsTheSteppers) {
  const StepperSetup<double> setup = setup_dt(0.005);
  for (const Side side : {Side::positive, Side::negative}) {
    const SideConstants k = side_constants(setup, side);
    const double x0 = side == Side::positive ? 0.03 : -0.02, xd0 = side == Side::positive ? 0.05 : -0.04;
    for (const double kc : {1.0, 1.3}) {
      for (const double kk : {1.0, 0.8}) {
        const Stepped st = stepper_step(setup, x0, xd0, kc, kk, 0.9);
        LONGS_EQUAL(0, st.impacts);
        double x1 = 0.0, xd1 = 0.0;
        om::newmark_step(setup.dt_s, k.k_s, k.f_s, kc, kk, x0, xd0, x1, xd1);
        check_close(st.x1, x1, 1e-12, 1e-15, "x1");
        check_close(st.xd1, xd1, 1e-12, 1e-15, "xd1");
      }
    }
  }
}

TEST(ObserverModel, TheGeneratedTransitionIsTheSteppersFiniteDifferences) {
  const StepperSetup<double> setup = setup_dt(0.005);
  const double e = 0.9;
  for (const Side side : {Side::positive, Side::negative}) {
    const SideConstants k = side_constants(setup, side);
    const double z0[6] = {side == Side::positive ? 0.03 : -0.02, side == Side::positive ? 0.05 : -0.04, e, 0.0,
                          1.2, 0.9};
    double fx[6], fv[6];
    om::newmark_jacobian(setup.dt_s, k.k_s, k.f_s, z0[om::C], z0[om::K], z0[om::X], z0[om::V], fx, fv);
    for (const int col : {int(om::X), int(om::V), int(om::C), int(om::K)}) {
      const double d = col == om::X || col == om::V ? 1e-6 : 1e-6;
      double zp[6], zm[6];
      for (int i = 0; i < 6; ++i) zp[i] = zm[i] = z0[i];
      zp[col] += d;
      zm[col] -= d;
      const Stepped p = stepper_step(setup, zp[om::X], zp[om::V], zp[om::C], zp[om::K], e);
      const Stepped m = stepper_step(setup, zm[om::X], zm[om::V], zm[om::C], zm[om::K], e);
      LONGS_EQUAL(0, p.impacts + m.impacts);
      const std::string name = std::string(side == Side::positive ? "+" : "-") + " column " + std::to_string(col);
      check_close((p.x1 - m.x1) / (2 * d), fx[col], 1e-6, 1e-9, name + " of row X");
      check_close((p.xd1 - m.xd1) / (2 * d), fv[col], 1e-6, 1e-9, name + " of row V");
    }
    // e and b do not enter the step between impacts.
    DOUBLES_EQUAL(0.0, fx[om::E] + fx[om::B] + fv[om::E] + fv[om::B], 0.0);
  }
}

// A short step (0.1 ms) that crosses the hinge: its finite differences are the saltation matrix up to the flow of
// the step's two pieces (O(h)), which the tolerances allow.
TEST(ObserverModel, TheGeneratedSaltationMatrixIsTheImpactsFiniteDifferences) {
  const double h = 1e-4;
  const StepperSetup<double> setup = setup_dt(h);
  const double e = 0.85, kc = 1.1;
  const double x0 = 4e-6, xd0 = -0.08;  // on side +, reaching the hinge half-way through the step
  const SideConstants before = side_constants(setup, Side::positive), after = side_constants(setup, Side::negative);
  double jx[6], jv[6];
  om::impact_saltation(xd0, before.f_s, after.f_s, e, kc, jx, jv);
  const double z0[3] = {x0, xd0, e};
  const int cols[3] = {om::X, om::V, om::E};
  const double steps[3] = {1e-8, 1e-6, 1e-6};
  for (int j = 0; j < 3; ++j) {
    double zp[3] = {z0[0], z0[1], z0[2]}, zm[3] = {z0[0], z0[1], z0[2]};
    zp[j] += steps[j];
    zm[j] -= steps[j];
    const Stepped p = stepper_step(setup, zp[0], zp[1], kc, 1.0, zp[2]);
    const Stepped m = stepper_step(setup, zm[0], zm[1], kc, 1.0, zm[2]);
    LONGS_EQUAL(2, p.impacts + m.impacts);
    const std::string name = "column " + std::to_string(cols[j]);
    // The flow over h moves x by ẋ·h: an absolute allowance of a few h on row X, and of h·(k + |a|/|ẋ|) on row V.
    check_close((p.x1 - m.x1) / (2 * steps[j]), jx[cols[j]], 0.02, 3 * h, name + " of row X");
    check_close((p.xd1 - m.xd1) / (2 * steps[j]), jv[cols[j]], 0.02, 0.05, name + " of row V");
  }
}

TEST(ObserverModel, TheGeneratedMeasurementsAreTheSteppersAndTheirFiniteDifferences) {
  const StepperSetup<double> setup = setup_dt(0.005);
  const double g_over_h1 = setup.g_mps2 / paper_wall().h1_m;
  const SideConstants k = side_constants(setup, Side::positive);
  // a_mid = ü + ẍ − G·x/h1 from the stepper's ẍ at (x, κc, κk), ü = 0.
  auto a_mid = [&](double x, double kc, double kk) {
    RockingStepper<double> s;
    s.init(setup);
    s.set_capacity_scales(kc, kk);
    s.set_state(x, 0.01, 0.0, 0.0);
    return s.state().xdd_mps2 - g_over_h1 * x;
  };
  const double x = 0.02, kc = 1.15, kk = 0.95;
  double h[6];
  const double a = om::acceleration_measurement(0.0, g_over_h1, k.k_s, k.f_s, kc, kk, x, h);
  check_close(a_mid(x, kc, kk), a, 1e-12, 1e-12, "a_mid");
  const double d = 1e-6;
  check_close((a_mid(x + d, kc, kk) - a_mid(x - d, kc, kk)) / (2 * d), h[om::X], 1e-6, 1e-8, "dA/dx");
  check_close((a_mid(x, kc + d, kk) - a_mid(x, kc - d, kk)) / (2 * d), h[om::C], 1e-6, 1e-8, "dA/dkc");
  check_close((a_mid(x, kc, kk + d) - a_mid(x, kc, kk - d)) / (2 * d), h[om::K], 1e-6, 1e-8, "dA/dkk");
  DOUBLES_EQUAL(0.0, h[om::V] + h[om::E] + h[om::B], 0.0);
  double hx[6];
  DOUBLES_EQUAL(0.023, om::displacement_measurement(0.02, 0.003, hx), 1e-15);
  DOUBLES_EQUAL(1.0, hx[om::X], 0.0);
  DOUBLES_EQUAL(1.0, hx[om::B], 0.0);
  DOUBLES_EQUAL(0.0, hx[om::V] + hx[om::E] + hx[om::C] + hx[om::K], 0.0);
}

// The committed header is the script's output (skipped without python3-sympy, failed for that under CI=true).
TEST(ObserverModel, TheGeneratedHeaderIsWhatTheDerivationWrites) {
  const std::string script = std::string(ROCKWATCH_TEST_DATA_DIR) + "/../../scripts/derive_observer.py";
  if (std::system("/usr/bin/python3 -c 'import sympy' >/dev/null 2>&1") != 0 &&
      rockwatch::test::skip_or_fail_in_ci("python3-sympy (Debian) for scripts/derive_observer.py")) {
    return;
  }
  const std::string command = "/usr/bin/python3 " + script + " --check >/dev/null";
  LONGS_EQUAL(0, std::system(command.c_str()));
}
