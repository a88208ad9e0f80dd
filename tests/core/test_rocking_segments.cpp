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

TEST(RockingSegments, ChatterIsCutAtEachArithmeticsBoundAndTheWallPutAtRest) {
  // r = 0.98 from 1 nm: bounces tens of microseconds apart at ~1e-4 m/s, far more than a 5 ms step holds. Each
  // segment ends in an impact; at the bound the wall is put at rest (rest_forced), whatever the arithmetic.
  const StepperSetup<double> setup = paper_setup(0.98, 0.005);
  RockingStepper<double> d;
  d.init(setup);
  d.set_state(1e-9, 0.0, 0.0, 0.0);
  const StepReport<double> dr = d.step(0.0, 0.0);
  LONGS_EQUAL(RockingStepper<double>::kMaxSegmentsPerStep, dr.segments);
  LONGS_EQUAL(RockingStepper<double>::kMaxSegmentsPerStep, dr.impacts_total);
  CHECK_TRUE(dr.rest_forced);
  CHECK_TRUE(dr.came_to_rest);
  CHECK_FALSE(d.moving());

  // The fixed-point stepper: kMaxSegmentsPerStep per step, within its sample budget of further segments.
  FixedRockingStepper f;
  CHECK(f.init(setup) == FixedSetupError::ok);
  f.set_state(LengthQ1_62(1e-9), SpeedQ3_60{}, AccelQ7_56{}, AccelQ7_56{});
  const FixedStepReport fr = f.step(AccelQ7_56{}, AccelQ7_56{});
  LONGS_EQUAL(FixedRockingStepper::kMaxSegmentsPerStep, fr.segments);
  LONGS_EQUAL(FixedRockingStepper::kMaxSegmentsPerStep, fr.impacts_total);
  CHECK_TRUE(fr.rest_forced);
  CHECK_FALSE(f.moving());

  // A budget of 3 further segments shared with the sample's other sub-steps: 4 segments, then rest; the budget is
  // spent, and the next sub-step (the wall at rest, no drive) needs none.
  f.set_state(LengthQ1_62(1e-9), SpeedQ3_60{}, AccelQ7_56{}, AccelQ7_56{});
  EventBudget budget{3};
  const FixedStepReport limited = f.step(AccelQ7_56{}, AccelQ7_56{}, budget);
  LONGS_EQUAL(4, limited.segments);
  LONGS_EQUAL(4, limited.impacts_total);
  CHECK_TRUE(limited.rest_forced);
  LONGS_EQUAL(0, budget.extra_segments);
  const FixedStepReport next = f.step(AccelQ7_56{}, AccelQ7_56{}, budget);
  LONGS_EQUAL(0, next.impacts_total);
  CHECK_FALSE(next.started);
  CHECK_FALSE(f.moving());

  // The double stepper spends from a budget in the same way (the chain gives it an unlimited one).
  d.set_state(1e-9, 0.0, 0.0, 0.0);
  EventBudget small{3};
  const StepReport<double> dl = d.step(0.0, 0.0, small);
  LONGS_EQUAL(4, dl.segments);
  CHECK_TRUE(dl.rest_forced);
}
