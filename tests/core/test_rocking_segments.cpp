// The one segment logic (core/rocking_segments.hpp) on both arithmetics: the impact and rest rules and the bounds on
// segments hold the same way in RockingStepper<double> and FixedRockingStepper.
#include <cmath>

#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch::core;

namespace {

StepperSetup<double> paper_setup(double r_energy, double dt_s) {
  StepperOptions o;
  o.dt_s = dt_s;
  return make_stepper_setup(paper_wall(), ModelKind::linear, r_energy, o);
}

}  // namespace

TEST_GROUP(RockingSegments){};

TEST(RockingSegments, AnImpactThatRestsTheWallReportsTheImpactLawsVelocityInBothArithmetics) {
  // r = 1e-6 (√r = 1e-3): a wall 1 nm from the hinge falls onto it at ≈ 7e-5 m/s, leaves it at ≈ 7e-8 m/s < v_rest
  // (1e-7) with no input driving it out, so the rest rule holds it. The report says ẋ⁺ = √r·ẋ⁻ (not 0) in both.
  const StepperSetup<double> setup = paper_setup(1e-6, 0.005);
  RockingStepper<double> d;
  d.init(setup);
  d.set_state(1e-9, 0.0, 0.0, 0.0);
  const StepReport<double> dr = d.step(0.0, 0.0);
  LONGS_EQUAL(1, dr.impacts_total);
  CHECK_TRUE(dr.came_to_rest);
  CHECK_FALSE(dr.rest_forced);
  CHECK_FALSE(d.moving());
  CHECK(dr.first_impact_v_before_mps < -1e-5);
  DOUBLES_EQUAL(setup.sqrt_r * dr.first_impact_v_before_mps, dr.first_impact_v_after_mps, 0.0);
  CHECK(std::fabs(dr.first_impact_v_after_mps) < setup.v_rest_mps);

  FixedRockingStepper f;
  CHECK(f.init(setup) == FixedSetupError::ok);
  f.set_state(LengthQ1_62(1e-9), SpeedQ3_60{}, AccelQ7_56{}, AccelQ7_56{});
  const FixedStepReport fr = f.step(AccelQ7_56{}, AccelQ7_56{});
  LONGS_EQUAL(1, fr.impacts_total);
  CHECK_TRUE(fr.came_to_rest);
  CHECK_FALSE(f.moving());
  // (ẋ⁻ itself differs by a few %: 8 Newton steps from the secant locate a crossing this skewed — 1 nm against a
  // 5 ms step — less closely than the double's regula falsi; the rule under test is what follows the crossing.)
  CHECK(fr.first_impact_v_before_mps < SpeedQ3_60(-1e-5));
  CHECK(fr.first_impact_v_after_mps == wide_mul<SpeedQ3_60>(f.setup().sqrt_r, fr.first_impact_v_before_mps));
  CHECK(fr.first_impact_v_after_mps != SpeedQ3_60{});
  CHECK(abs(fr.first_impact_v_after_mps) < f.setup().v_rest_mps);
}

TEST(RockingSegments, TheChatterRuleLocatesKImpactsAStepThenRestsTheWallInBothArithmetics) {
  // r = 0.98 from 1 nm: bounces tens of microseconds apart at ~1e-4 m/s, far more than a 5 ms step holds. The first K
  // impacts of the step are located; the next crossing is not: the wall rests on the hinge at the step end
  // (rest_forced), the same rule and the same count in both arithmetics (SPEC §3).
  const StepperSetup<double> setup = paper_setup(0.98, 0.005);
  const int k = kMaxImpactsPerSubstep;
  RockingStepper<double> d;
  d.init(setup);
  d.set_state(1e-9, 0.0, 0.0, 0.0);
  const StepReport<double> dr = d.step(0.0, 0.0);
  LONGS_EQUAL(k + 1, dr.segments);
  LONGS_EQUAL(k, dr.impacts_total);
  LONGS_EQUAL(k, dr.events_located);
  CHECK_TRUE(dr.rest_forced);
  CHECK_TRUE(dr.came_to_rest);
  CHECK_FALSE(dr.work_shed);
  CHECK_FALSE(d.moving());
  DOUBLES_EQUAL(0.0, d.state().x_m, 0.0);
  DOUBLES_EQUAL(0.0, d.state().xd_mps, 0.0);
  // At rest with no drive the next step does nothing.
  const StepReport<double> dn = d.step(0.0, 0.0);
  LONGS_EQUAL(0, dn.impacts_total);
  CHECK_FALSE(dn.started);

  FixedRockingStepper f;
  CHECK(f.init(setup) == FixedSetupError::ok);
  f.set_state(LengthQ1_62(1e-9), SpeedQ3_60{}, AccelQ7_56{}, AccelQ7_56{});
  const FixedStepReport fr = f.step(AccelQ7_56{}, AccelQ7_56{});
  LONGS_EQUAL(k + 1, fr.segments);
  LONGS_EQUAL(k, fr.impacts_total);
  LONGS_EQUAL(k, fr.events_located);
  CHECK_TRUE(fr.rest_forced);
  CHECK_FALSE(fr.work_shed);
  CHECK_FALSE(f.moving());
  const FixedStepReport fn = f.step(AccelQ7_56{}, AccelQ7_56{});
  LONGS_EQUAL(0, fn.impacts_total);
  CHECK_FALSE(fn.started);
}

TEST(RockingSegments, AfterTheChatterRuleTheStartRuleTakesOverWhenTheGroundDrivesTheWallOut) {
  // The same chatter, then a ground acceleration beyond the threshold in the next step: the wall put at rest by the
  // rule starts again in that step (SPEC §2), in both arithmetics.
  const StepperSetup<double> setup = paper_setup(0.98, 0.005);
  const double beyond_mps2 = 3.0 * threshold_mps2(setup.model, Side::negative, setup.g_mps2);
  RockingStepper<double> d;
  d.init(setup);
  d.set_state(1e-9, 0.0, 0.0, 0.0);
  CHECK_TRUE(d.step(0.0, 0.0).rest_forced);
  const StepReport<double> dn = d.step(beyond_mps2, 0.0);
  CHECK_TRUE(dn.started);
  CHECK_TRUE(d.moving());

  FixedRockingStepper f;
  CHECK(f.init(setup) == FixedSetupError::ok);
  f.set_state(LengthQ1_62(1e-9), SpeedQ3_60{}, AccelQ7_56{}, AccelQ7_56{});
  CHECK_TRUE(f.step(AccelQ7_56{}, AccelQ7_56{}).rest_forced);
  const FixedStepReport fn = f.step(AccelQ7_56(beyond_mps2), AccelQ7_56{});
  CHECK_TRUE(fn.started);
  CHECK_TRUE(f.moving());
  CHECK(d.side() == f.side());
}
