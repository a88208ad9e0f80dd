// The rocking stepper on its own: free rocking against the reference, energy, symmetry, start and rest logic.
#include <cmath>
#include <vector>

#include "reference_data.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch::core;
using rockwatch::test::rel_tol;

namespace {

struct Impact {
  double t_s, v_before, v_after;
};

RockingStepper<double> make_stepper(double r_energy, double dt_s, ModelKind kind = ModelKind::linear,
                                    double kappa = 2.0) {
  StepperOptions o;
  o.dt_s = dt_s;
  o.kappa = kappa;
  RockingStepper<double> s;
  s.init(make_stepper_setup(paper_wall(), kind, r_energy, o));
  return s;
}

// Free rocking from rest at x0 (no input) for `steps`, collecting impacts.
std::vector<Impact> free_rocking(RockingStepper<double>& s, double x0, int steps, std::size_t max_impacts) {
  s.set_state(x0, 0.0, 0.0, 0.0);
  std::vector<Impact> impacts;
  const double dt = s.setup().dt_s;
  for (int n = 0; n < steps && impacts.size() < max_impacts; ++n) {
    const StepReport<double> rep = s.step(0.0, 0.0);
    if (rep.impacts_total > 0) {
      impacts.push_back({(double(n) + rep.first_impact_fraction) * dt, rep.first_impact_v_before_mps,
                         rep.first_impact_v_after_mps});
    }
  }
  return impacts;
}

double free_energy(const RockingStepper<double>& s) {
  const Coefficients<double> k = evaluate(s.setup().model, s.side(), 0.0, 9.81);
  return mechanical_energy(k, s.state().x_m, s.state().xd_mps);
}

}  // namespace

TEST_GROUP(RockingStepper) {
  nlohmann::json ref;
  void setup() override { ref = rockwatch::test::load_reference(); }
};

TEST(RockingStepper, FreeRockingImpactsMatchTheReferenceNewmark) {
  // Same discrete algorithm as the reference's Newmark: impact times and velocities agree to ~1e-9.
  const auto& fr = ref.at("free_rocking_x0_0.05_paper_linear_first_impacts_t_vbefore_vafter");
  const struct {
    const char* key;
    double r;
  } cases[] = {{"r_exp_newmark_dt0.005_substep", r_exp(paper_wall())},
               {"r_ana_newmark_dt0.005_substep", r_ana(paper_wall())}};
  for (const auto& c : cases) {
    RockingStepper<double> s = make_stepper(c.r, 0.005);
    const auto& expected = fr.at(c.key);
    const std::vector<Impact> got = free_rocking(s, 0.05, 2000, expected.size());
    LONGS_EQUAL(expected.size(), got.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      DOUBLES_EQUAL(expected[i][0].get<double>(), got[i].t_s, 1e-9);
      DOUBLES_EQUAL(expected[i][1].get<double>(), got[i].v_before, 1e-9);
      DOUBLES_EQUAL(expected[i][2].get<double>(), got[i].v_after, 1e-9);
    }
  }
}

TEST(RockingStepper, FreeRockingConvergesToTheHighAccuracySolution) {
  // Against the event-driven solution: error shrinks as Δt² (ratio ≈ 4 when Δt halves, impacts included).
  const auto& expected = ref.at("free_rocking_x0_0.05_paper_linear_first_impacts_t_vbefore_vafter").at("r_exp");
  double previous_error = 0.0;
  for (double dt : {0.004, 0.002, 0.001}) {
    RockingStepper<double> s = make_stepper(r_exp(paper_wall()), dt);
    const std::vector<Impact> got = free_rocking(s, 0.05, 100000, expected.size());
    LONGS_EQUAL(expected.size(), got.size());
    const double error = std::fabs(got.back().t_s - expected.back()[0].get<double>());
    if (previous_error > 0.0) {
      const double ratio = previous_error / error;
      CHECK(ratio > 3.6 && ratio < 4.4);
    }
    previous_error = error;
  }
  CHECK(previous_error < 1e-5);
}

TEST(RockingStepper, EnergyIsConservedWithoutRestitutionLoss) {
  // r = 1 and no input: trapezoidal Newmark conserves the energy of each linear side exactly, and the impact
  // at x = 0 keeps the kinetic energy, so E drifts only by rounding over many impacts.
  RockingStepper<double> s = make_stepper(1.0, 0.005);
  s.set_state(0.06, 0.0, 0.0, 0.0);
  const double e0 = free_energy(s);
  int impacts = 0;
  for (int n = 0; n < 4000; ++n) impacts += s.step(0.0, 0.0).impacts_total;
  CHECK(impacts > 20);
  DOUBLES_EQUAL(e0, free_energy(s), 1e-9 * std::fabs(e0));
  CHECK_TRUE(s.moving());
}

TEST(RockingStepper, FreeRockingPeriodMatchesTheClosedForm) {
  // With r = 1 the wall rocks periodically; the time between impacts in the same direction is the period.
  for (const auto& row : ref.at("free_rocking_period_r1")) {
    const double x0 = row.at("x0"), period = row.at("T_closed_form_paper_linear");
    RockingStepper<double> s = make_stepper(1.0, 1e-4);
    const std::vector<Impact> got = free_rocking(s, x0, 200000, 3);
    LONGS_EQUAL(3, got.size());
    DOUBLES_EQUAL(period, got[2].t_s - got[0].t_s, 2e-5 * period);
  }
}

TEST(RockingStepper, MirrorSymmetry) {
  // ü → −ü gives x → −x for a symmetric wall: same numbers, opposite sign, at every step.
  RockingStepper<double> a = make_stepper(r_exp(paper_wall()), 0.005);
  RockingStepper<double> b = make_stepper(r_exp(paper_wall()), 0.005);
  int impacts = 0;
  for (int n = 1; n <= 1000; ++n) {
    const double t = n * 0.005;
    const double ug = t < 2.0 ? 2.5 * std::sin(2.0 * M_PI * t / 0.4) + 0.8 * std::sin(2.0 * M_PI * t / 0.13) : 0.0;
    const StepReport<double> ra = a.step(ug, 0.3 * ug);
    const StepReport<double> rb = b.step(-ug, 0.3 * ug);
    impacts += ra.impacts_total;
    LONGS_EQUAL(ra.impacts_total, rb.impacts_total);
    DOUBLES_EQUAL(a.state().x_m, -b.state().x_m, 1e-15);
    DOUBLES_EQUAL(a.state().xd_mps, -b.state().xd_mps, 1e-14);
  }
  CHECK(impacts > 3);
}

TEST(RockingStepper, StartsExactlyWhereTheInputCrossesTheThreshold) {
  const double thr = threshold_mps2(model_constants(paper_wall(), ModelKind::linear), Side::positive, 9.81);
  RockingStepper<double> s = make_stepper(r_exp(paper_wall()), 0.01);
  s.reset(0.0, 0.0);
  // Input ramps from 0 to −2·thr over one step: rocking towards x > 0 starts half way.
  const StepReport<double> rep = s.step(-2.0 * thr, 0.0);
  CHECK_TRUE(rep.started);
  DOUBLES_EQUAL(0.5, rep.start_fraction, 1e-12);
  CHECK_TRUE(s.side() == Side::positive);
  CHECK(s.state().x_m > 0.0);
  // Just below the threshold (either sign) nothing moves.
  RockingStepper<double> quiet = make_stepper(r_exp(paper_wall()), 0.01);
  for (int n = 0; n < 500; ++n) {
    const StepReport<double> r = quiet.step((n % 2 ? 1.0 : -1.0) * thr * 0.999, 0.0);
    CHECK_FALSE(r.started);
  }
  CHECK_FALSE(quiet.moving());
  DOUBLES_EQUAL(0.0, quiet.state().x_m, 0.0);
}

TEST(RockingStepper, VerticalAccelerationLowersTheThreshold) {
  // With v̈ = −0.3 g the threshold drops to 0.08 g (reference): 0.09 g starts rocking, which it would not at v̈ = 0.
  const double g = 9.81;
  RockingStepper<double> s = make_stepper(r_exp(paper_wall()), 0.005);
  s.reset(0.0, -0.3 * g);
  CHECK_TRUE(s.step(0.09 * g, -0.3 * g).started);
  CHECK_TRUE(s.side() == Side::negative);
  RockingStepper<double> t = make_stepper(r_exp(paper_wall()), 0.005);
  CHECK_FALSE(t.step(0.09 * g, 0.0).started);
}

TEST(RockingStepper, LiftOffIsReportedAndTheStateHeld) {
  RockingStepper<double> s = make_stepper(r_exp(paper_wall()), 0.005);
  s.set_state(0.02, 0.1, 0.0, 0.0);
  const MotionState<double> before = s.state();
  const StepReport<double> rep = s.step(0.0, -9.81);
  CHECK_TRUE(rep.input_invalid);
  DOUBLES_EQUAL(before.x_m, s.state().x_m, 0.0);
  CHECK_FALSE(s.step(0.0, 0.0).input_invalid);
}

TEST(RockingStepper, ComesToRestAndStaysThere) {
  // Strong restitution loss: the motion dies out, the rest rule ends the impact cascade (no Zeno),
  // and the wall then stays exactly at rest.
  RockingStepper<double> s = make_stepper(0.3, 0.005);
  s.set_state(0.03, 0.0, 0.0, 0.0);
  bool rested = false;
  int counted = 0;
  for (int n = 0; n < 2000; ++n) {
    const StepReport<double> rep = s.step(0.0, 0.0);
    counted += rep.impacts_counted;
    rested = rested || rep.came_to_rest;
  }
  CHECK_TRUE(rested);
  CHECK_FALSE(s.moving());
  DOUBLES_EQUAL(0.0, s.state().x_m, 0.0);
  DOUBLES_EQUAL(0.0, s.state().xd_mps, 0.0);
  CHECK(counted > 3 && counted < 20);
}

TEST(RockingStepper, ZeroRestitutionStopsAtTheFirstImpact) {
  RockingStepper<double> s = make_stepper(0.0, 0.005);
  s.set_state(0.03, 0.0, 0.0, 0.0);
  int total = 0;
  for (int n = 0; n < 400; ++n) total += s.step(0.0, 0.0).impacts_total;
  LONGS_EQUAL(1, total);
  CHECK_FALSE(s.moving());
}

TEST(RockingStepper, CollapseIsLocatedInsideTheStepAndLatches) {
  // Released beyond x_inst with no input the wall falls; collapse at exactly κ·x_inst.
  RockingStepper<double> s = make_stepper(r_exp(paper_wall()), 0.005, ModelKind::linear, 2.0);
  const double xi = s.x_inst_m(Side::positive);
  s.set_state(1.05 * xi, 0.0, 0.0, 0.0);
  bool collapsed = false;
  for (int n = 0; n < 1000 && !collapsed; ++n) {
    const StepReport<double> rep = s.step(0.0, 0.0);
    if (rep.collapsed) {
      collapsed = true;
      CHECK(rep.collapse_fraction > 0.0 && rep.collapse_fraction <= 1.0);
    }
  }
  CHECK_TRUE(collapsed);
  CHECK_TRUE(s.collapsed());
  DOUBLES_EQUAL(2.0 * xi, s.state().x_m, 1e-15);
  const StepReport<double> after = s.step(-5.0, 0.0);
  CHECK_FALSE(after.started);
  DOUBLES_EQUAL(2.0 * xi, s.state().x_m, 1e-15);
}

TEST(RockingStepper, FullModelFreeRockingStaysCloseToLinear) {
  // The full model's extra terms are < 2 % (SPEC §1): impact velocities within a few per cent of linear.
  RockingStepper<double> lin = make_stepper(r_exp(paper_wall()), 0.005, ModelKind::linear);
  RockingStepper<double> full = make_stepper(r_exp(paper_wall()), 0.005, ModelKind::full);
  const std::vector<Impact> a = free_rocking(lin, 0.05, 2000, 4);
  const std::vector<Impact> b = free_rocking(full, 0.05, 2000, 4);
  LONGS_EQUAL(4, b.size());
  for (std::size_t i = 0; i < 4; ++i) {
    DOUBLES_EQUAL(a[i].v_before, b[i].v_before, 0.02 * std::fabs(a[i].v_before));
    CHECK(std::fabs(a[i].v_before - b[i].v_before) > 0.0);
  }
}

TEST(RockingStepper, AsymmetricWallUsesEachSidesThresholdAndInstability) {
  // The reference's general wall (Fp, a ≠ a', h1 ≠ h2): thresholds and x_inst differ per side. A slow ramp
  // towards each side must start rocking exactly at that side's threshold and collapse at that side's κ·x_inst.
  WallParameters w;
  w.b_m = 0.2;
  w.h1_m = 2.0;
  w.h2_m = 1.3;
  w.rho_kgpm3 = 1900.0;
  w.fp_npm = 8000.0;
  w.a = 0.3;
  w.a_prime = 0.6;
  const ModelConstants<double> c = model_constants(w, ModelKind::linear);
  for (Side side : {Side::positive, Side::negative}) {
    const double thr = threshold_mps2(c, side, 9.81);
    const double rate = 2.0;  // |ü| grows 2 m/s² per second, towards driving the wall to `side`
    const double dir = side == Side::positive ? -1.0 : 1.0;  // ü < 0 drives x > 0
    StepperOptions o;
    o.dt_s = 0.005;
    RockingStepper<double> s;
    s.init(make_stepper_setup(w, ModelKind::linear, r_exp(w), o));
    double t_start = -1.0;
    bool collapsed = false;
    for (int n = 0; n < 4000 && !collapsed; ++n) {
      const StepReport<double> rep = s.step(dir * rate * (n + 1) * 0.005, 0.0);
      if (rep.started) t_start = (n + rep.start_fraction) * 0.005;
      collapsed = rep.collapsed;
    }
    DOUBLES_EQUAL(thr / rate, t_start, 1e-12);
    CHECK_TRUE(collapsed);
    CHECK_TRUE(s.side() == side);
    DOUBLES_EQUAL(2.0 * x_inst_m(c, side, 9.81), std::fabs(s.state().x_m), 1e-14);
  }
  CHECK(std::fabs(threshold_mps2(c, Side::positive, 9.81) - threshold_mps2(c, Side::negative, 9.81)) > 0.5);
}
