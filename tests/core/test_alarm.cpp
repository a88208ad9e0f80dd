// The instability alarm: the state machine (levels, hold time, latch, reason bits) and the indicators it acts on,
// checked against free rocking of the linear model, whose motion about x_inst has a closed form
// (y(t) = y0 cosh ωt + (ẏ0/ω) sinh ωt with y = s·x − x_inst, ẏ = s·ẋ).
#include <cmath>
#include <cstdint>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/instability_indicators.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch::core;

namespace {

AlarmConditions quiet_conditions() { return AlarmConditions{}; }

AlarmConditions rocking_conditions() {
  AlarmConditions c;
  c.moving = true;
  return c;
}

AlarmConditions warning_conditions() {
  AlarmConditions c = rocking_conditions();
  c.over_warning_displacement = true;
  return c;
}

AlarmConditions imminent_conditions() {
  AlarmConditions c = warning_conditions();
  c.energy_over_barrier_outward = true;
  return c;
}

AlarmConditions collapse_conditions() {
  AlarmConditions c;
  c.over_warning_displacement = true;
  c.over_instability_displacement = true;
  c.over_collapse_displacement = true;
  return c;
}

InstabilityAlarm make_alarm(std::uint32_t hold) {
  InstabilityAlarm a;
  a.init(hold);
  return a;
}

StepperSetup<double> paper_setup(double dt_s, ModelKind kind = ModelKind::linear, double kappa = 2.0,
                                 double r_energy = 1.0) {
  StepperOptions o;
  o.dt_s = dt_s;
  o.kappa = kappa;
  return make_stepper_setup(paper_wall(), kind, r_energy, o);
}

// Outward speed that gives energy ratio ρ at |x| = x_abs on a side with x_inst and ω (linear model).
double outward_speed(double rho, double x_abs, double x_inst, double omega) {
  const double y = x_abs - x_inst;
  return std::sqrt(omega * omega * (y * y + (rho - 1.0) * x_inst * x_inst));
}

struct Crossing {
  bool reached = false;
  double t_s = 0.0;
};

// Steps free motion (no input) until |x| reaches x_inst, located inside the step by the stepper.
Crossing time_to_exceed(RockingStepper<double>& s, int max_steps) {
  const double dt = s.setup().dt_s;
  for (int n = 0; n < max_steps; ++n) {
    const StepReport<double> rep = s.step(0.0, 0.0);
    if (rep.exceeded) return Crossing{true, (double(n) + rep.exceed_fraction) * dt};
  }
  return Crossing{};
}

}  // namespace

TEST_GROUP(AlarmStateMachine){};

TEST(AlarmStateMachine, LevelNamesAndSettingsBounds) {
  STRCMP_EQUAL("QUIET", alarm_level_name(AlarmLevel::quiet));
  STRCMP_EQUAL("ROCKING", alarm_level_name(AlarmLevel::rocking));
  STRCMP_EQUAL("WARNING", alarm_level_name(AlarmLevel::warning));
  STRCMP_EQUAL("IMMINENT", alarm_level_name(AlarmLevel::imminent));
  STRCMP_EQUAL("COLLAPSED", alarm_level_name(AlarmLevel::collapsed));

  CHECK_TRUE(alarm_settings_valid(AlarmSettings{}));
  CHECK_TRUE(alarm_settings_valid(AlarmSettings{1.0, 0.0, 1.0}));
  CHECK_FALSE(alarm_settings_valid(AlarmSettings{0.0, 1.0, 1.0}));
  CHECK_FALSE(alarm_settings_valid(AlarmSettings{1.01, 1.0, 1.0}));
  CHECK_FALSE(alarm_settings_valid(AlarmSettings{0.4, -0.1, 1.0}));
  CHECK_FALSE(alarm_settings_valid(AlarmSettings{0.4, 1.0, 0.99}));
  CHECK_FALSE(alarm_settings_valid(AlarmSettings{std::nan(""), 1.0, 1.0}));
  CHECK_FALSE(alarm_settings_valid(AlarmSettings{0.4, std::nan(""), 1.0}));
  CHECK_FALSE(alarm_settings_valid(AlarmSettings{0.4, 1.0, std::nan("")}));

  LONGS_EQUAL(200, hold_samples(AlarmSettings{0.4, 1.0, 1.0}, 0.005));
  LONGS_EQUAL(100, hold_samples(AlarmSettings{0.4, 1.0, 1.0}, 0.01));
  LONGS_EQUAL(0, hold_samples(AlarmSettings{0.4, 0.0, 1.0}, 0.005));
  LONGS_EQUAL(3, hold_samples(AlarmSettings{0.4, 0.0149, 1.0}, 0.005));  // 2.98 rounds to 3
}

TEST(AlarmStateMachine, StartsQuietAndRisesAtOnce) {
  InstabilityAlarm a = make_alarm(100);
  CHECK_TRUE(a.level() == AlarmLevel::quiet);
  const AlarmUpdate u = a.update(imminent_conditions());
  CHECK_TRUE(u.changed);
  CHECK_TRUE(u.previous == AlarmLevel::quiet);
  CHECK_TRUE(u.level == AlarmLevel::imminent);  // straight past ROCKING and WARNING
  LONGS_EQUAL(alarm_reason::moving | alarm_reason::over_warning_displacement |
                  alarm_reason::energy_over_barrier_outward,
              u.reasons);

  InstabilityAlarm b = make_alarm(100);
  CHECK_TRUE(b.update(rocking_conditions()).level == AlarmLevel::rocking);
  CHECK_TRUE(b.update(warning_conditions()).level == AlarmLevel::warning);
  AlarmConditions by_displacement = warning_conditions();
  by_displacement.over_instability_displacement = true;  // IMMINENT by displacement alone, no energy flag
  const AlarmUpdate u2 = b.update(by_displacement);
  CHECK_TRUE(u2.level == AlarmLevel::imminent);
  CHECK_TRUE((u2.reasons & alarm_reason::over_instability_displacement) != 0);
  CHECK_TRUE((u2.reasons & alarm_reason::energy_over_barrier_outward) == 0);
  const AlarmUpdate same = b.update(by_displacement);
  CHECK_FALSE(same.changed);
  CHECK_TRUE(same.previous == AlarmLevel::imminent);
}

TEST(AlarmStateMachine, FallsExactlyAfterTheHoldTimeNotOneSampleEarlier) {
  // hold 1 s at 0.01 s: 100 samples. The level falls on the 101st consecutive sample below, i.e. once the conditions
  // have been below for the whole hold time (100 sample intervals after the first sample below).
  const std::uint32_t hold = hold_samples(AlarmSettings{0.4, 1.0, 1.0}, 0.01);
  InstabilityAlarm a = make_alarm(hold);
  a.update(warning_conditions());
  for (std::uint32_t n = 1; n <= hold; ++n) {
    const AlarmUpdate u = a.update(rocking_conditions());
    CHECK_TRUE(u.level == AlarmLevel::warning);
    CHECK_FALSE(u.changed);
    LONGS_EQUAL(alarm_reason::moving | alarm_reason::held, u.reasons);
  }
  const AlarmUpdate fall = a.update(rocking_conditions());
  CHECK_TRUE(fall.changed);
  CHECK_TRUE(fall.previous == AlarmLevel::warning);
  CHECK_TRUE(fall.level == AlarmLevel::rocking);
  LONGS_EQUAL(alarm_reason::moving, fall.reasons);  // no longer held
}

TEST(AlarmStateMachine, FallsStraightToTheLevelTheConditionsGive) {
  InstabilityAlarm a = make_alarm(5);
  a.update(imminent_conditions());
  for (int n = 0; n < 5; ++n) CHECK_TRUE(a.update(quiet_conditions()).level == AlarmLevel::imminent);
  const AlarmUpdate u = a.update(quiet_conditions());
  CHECK_TRUE(u.level == AlarmLevel::quiet);  // not through WARNING and ROCKING
  CHECK_TRUE(u.previous == AlarmLevel::imminent);
}

TEST(AlarmStateMachine, ConditionsBackAtTheLevelRestartTheHold) {
  InstabilityAlarm a = make_alarm(10);
  a.update(warning_conditions());
  for (int n = 0; n < 8; ++n) a.update(rocking_conditions());
  CHECK_TRUE(a.update(warning_conditions()).level == AlarmLevel::warning);  // back at the level: count restarts
  for (int n = 0; n < 10; ++n) CHECK_TRUE(a.update(rocking_conditions()).level == AlarmLevel::warning);
  CHECK_TRUE(a.update(rocking_conditions()).level == AlarmLevel::rocking);
}

TEST(AlarmStateMachine, HigherConditionsDuringTheHoldRaiseAtOnce) {
  InstabilityAlarm a = make_alarm(10);
  a.update(warning_conditions());
  a.update(rocking_conditions());
  const AlarmUpdate u = a.update(imminent_conditions());
  CHECK_TRUE(u.level == AlarmLevel::imminent);
  CHECK_TRUE((u.reasons & alarm_reason::held) == 0);
}

TEST(AlarmStateMachine, ZeroHoldFallsAtTheFirstSampleBelow) {
  InstabilityAlarm a = make_alarm(0);
  a.update(warning_conditions());
  CHECK_TRUE(a.update(rocking_conditions()).level == AlarmLevel::rocking);
  CHECK_TRUE(a.update(quiet_conditions()).level == AlarmLevel::quiet);
}

TEST(AlarmStateMachine, CollapseIsLatchedUntilReset) {
  InstabilityAlarm a = make_alarm(0);
  a.update(warning_conditions());
  const AlarmUpdate c = a.update(collapse_conditions());
  CHECK_TRUE(c.level == AlarmLevel::collapsed);
  CHECK_TRUE(c.changed);
  for (int n = 0; n < 1000; ++n) {
    const AlarmUpdate u = a.update(quiet_conditions());
    CHECK_TRUE(u.level == AlarmLevel::collapsed);
    LONGS_EQUAL(alarm_reason::over_collapse_displacement, u.reasons);  // latched, and said so
  }
  a.reset();
  CHECK_TRUE(a.level() == AlarmLevel::quiet);
  CHECK_TRUE(a.update(rocking_conditions()).level == AlarmLevel::rocking);
}

TEST(AlarmStateMachine, EveryConditionHasItsReasonBit) {
  const struct {
    bool AlarmConditions::*field;
    std::uint32_t bit;
  } cases[] = {{&AlarmConditions::moving, alarm_reason::moving},
               {&AlarmConditions::over_warning_displacement, alarm_reason::over_warning_displacement},
               {&AlarmConditions::energy_over_barrier_outward, alarm_reason::energy_over_barrier_outward},
               {&AlarmConditions::over_instability_displacement, alarm_reason::over_instability_displacement},
               {&AlarmConditions::over_collapse_displacement, alarm_reason::over_collapse_displacement},
               {&AlarmConditions::input_invalid, alarm_reason::input_invalid},
               {&AlarmConditions::arithmetic_saturated, alarm_reason::arithmetic_saturated}};
  for (const auto& c : cases) {
    InstabilityAlarm a = make_alarm(0);
    AlarmConditions k;
    k.*(c.field) = true;
    LONGS_EQUAL(c.bit, a.update(k).reasons);
  }
  // Data-quality bits alone raise nothing: the state is held, the level follows the physical conditions.
  InstabilityAlarm a = make_alarm(0);
  AlarmConditions k;
  k.input_invalid = true;
  k.arithmetic_saturated = true;
  CHECK_TRUE(a.update(k).level == AlarmLevel::quiet);
  // The bits are distinct.
  std::uint32_t all = 0;
  for (const auto& c : cases) {
    LONGS_EQUAL(0, all & c.bit);
    all |= c.bit;
  }
  LONGS_EQUAL(0, all & alarm_reason::held);
}

// The margin's rule alone at the barrier (margin 1, no horizon, from the vertical): what these tests check is that
// rule; the defaults' horizon and energy_min_x (2026-12-01) have tests of their own below.
const AlarmSettings kMarginOnly{0.4, 1.0, 1.0, 0.0, 0.0};

TEST_GROUP(InstabilityIndicators) {
  StepperSetup<double> wall_setup = paper_setup(0.001);
  InstabilityConstants<double> constants = make_instability_constants(wall_setup, kMarginOnly);
  RockingStepper<double> stepper;
  void setup() override { stepper.init(wall_setup); }
};

TEST(InstabilityIndicators, ConstantsOfThePaperWall) {
  // SPEC §1 reference: p1 = 212.742857, p4 = −3520.068245 (ü = v̈ = 0); x_inst = p6/p4 = 0.1003276 m.
  const double omega2 = 3520.068245 / 212.742857;
  for (int i = 0; i < 2; ++i) {
    DOUBLES_EQUAL(omega2, constants.omega2_rps2[i], 1e-6);
    DOUBLES_EQUAL(std::sqrt(omega2), constants.omega_rps[i], 1e-6);
    DOUBLES_EQUAL(0.1003276, constants.x_inst_m[i], 1e-7);
    DOUBLES_EQUAL(0.4 * constants.x_inst_m[i], constants.x_warning_m[i], 1e-15);
  }
  DOUBLES_EQUAL(1.0, constants.energy_margin, 0.0);
  DOUBLES_EQUAL(kInstabilityPredictionCap_s, constants.t_max_s, 0.0);

  // The full model: the same ω (p1, p4 do not depend on the model kind), its own x_inst (= b for this wall).
  const InstabilityConstants<double> full = make_instability_constants(paper_setup(0.001, ModelKind::full), {});
  DOUBLES_EQUAL(constants.omega_rps[1], full.omega_rps[1], 1e-15);
  DOUBLES_EQUAL(0.1, full.x_inst_m[1], 1e-6);
}

TEST(InstabilityIndicators, EnergyRatioIsOneAtTheInstabilityPointAtRestAndZeroAtTheVertical) {
  const double x_inst = constants.x_inst_m[1];
  for (const double sign : {1.0, -1.0}) {
    stepper.set_state(sign * x_inst, 0.0, 0.0, 0.0);
    const InstabilityIndicators<double> ind = evaluate_instability(constants, stepper, StepReport<double>{});
    DOUBLES_EQUAL(1.0, ind.energy_ratio, 1e-12);
    CHECK_TRUE(ind.conditions.over_instability_displacement);
    CHECK_TRUE(ind.conditions.over_warning_displacement);
    CHECK_TRUE(ind.t_valid);
    DOUBLES_EQUAL(0.0, ind.t_to_instability_s, 0.0);
    CHECK_FALSE(ind.conditions.energy_over_barrier_outward);  // not moving outward
  }
  stepper.reset(0.0, 0.0);
  const InstabilityIndicators<double> rest = evaluate_instability(constants, stepper, StepReport<double>{});
  DOUBLES_EQUAL(0.0, rest.energy_ratio, 1e-12);
  CHECK_FALSE(rest.conditions.moving);
  CHECK_FALSE(rest.t_valid);
  CHECK_FALSE(rest.conditions.over_warning_displacement);
}

TEST(InstabilityIndicators, EnergyRatioIsTheEnergyOverTheBarrierOfTheLinearModel) {
  const double barrier = energy_barrier_jpm(wall_setup.model, Side::positive, 9.81);
  const double states[][2] = {{0.03, 0.1}, {-0.07, 0.2}, {0.09, -0.05}, {-0.01, -0.4}, {0.12, 0.3}};
  for (const auto& st : states) {
    stepper.set_state(st[0], st[1], 0.0, 0.0);
    const Coefficients<double> k = evaluate(wall_setup.model, stepper.side(), 0.0, 9.81);
    const double expected = mechanical_energy(k, st[0], st[1]) / barrier;
    DOUBLES_EQUAL(expected, evaluate_instability(constants, stepper, StepReport<double>{}).energy_ratio, 1e-12);
  }
}

TEST(InstabilityIndicators, DisplacementConditions) {
  const double x_inst = constants.x_inst_m[0];
  const struct {
    double x;
    bool warning, instability;
  } cases[] = {{0.399 * x_inst, false, false}, {-0.4 * x_inst, true, false}, {0.9 * x_inst, true, false},
               {-x_inst, true, true},          {1.5 * x_inst, true, true}};
  for (const auto& c : cases) {
    stepper.set_state(c.x, -0.01 * c.x, 0.0, 0.0);  // moving inward: no energy flag
    const AlarmConditions k = evaluate_instability(constants, stepper, StepReport<double>{}).conditions;
    CHECK_TRUE(k.moving);
    CHECK_EQUAL(c.warning, k.over_warning_displacement);
    CHECK_EQUAL(c.instability, k.over_instability_displacement);
    CHECK_FALSE(k.energy_over_barrier_outward);
    CHECK_FALSE(k.over_collapse_displacement);
  }
  StepReport<double> invalid;
  invalid.input_invalid = true;
  CHECK_TRUE(evaluate_instability(constants, stepper, invalid).conditions.input_invalid);
}

TEST(InstabilityIndicators, PredictedTimeMatchesTheStepperAndTheClosedFormAboveTheBarrier) {
  const double x_inst = constants.x_inst_m[1], omega = constants.omega_rps[1], dt = wall_setup.dt_s;
  for (const double rho : {1.0005, 1.01, 1.2, 2.0}) {
    for (const double sign : {1.0, -1.0}) {
      for (const double x0_abs : {0.0, 0.02, 0.06}) {
        const double v0 = outward_speed(rho, x0_abs, x_inst, omega);
        stepper.set_state(sign * x0_abs, sign * v0, 0.0, 0.0);
        const InstabilityIndicators<double> ind = evaluate_instability(constants, stepper, StepReport<double>{});
        DOUBLES_EQUAL(rho, ind.energy_ratio, 1e-9);
        CHECK_TRUE(ind.conditions.energy_over_barrier_outward);
        CHECK_TRUE(ind.t_valid);
        CHECK_TRUE(ind.t_to_instability_s > 0.0);

        // Closed form: y(t) = y0 cosh ωt + (ẏ0/ω) sinh ωt is zero at the predicted time.
        const double y0 = x0_abs - x_inst, t = ind.t_to_instability_s;
        DOUBLES_EQUAL(0.0, y0 * std::cosh(omega * t) + v0 / omega * std::sinh(omega * t), 1e-12);

        // The stepper (Newmark, free motion) reaches x_inst when predicted, within two steps (in fact far closer:
        // the trapezoidal rule's phase error is (ω dt)²/12 relative).
        const Crossing reached = time_to_exceed(stepper, 200000);
        CHECK_TRUE(reached.reached);
        DOUBLES_EQUAL(t, reached.t_s, 2.0 * dt);
        DOUBLES_EQUAL(t, reached.t_s, 1e-5 * t + 1e-9);
      }
    }
  }
}

TEST(InstabilityIndicators, PredictionCountsDownAlongTheFreeTrajectory) {
  const double x_inst = constants.x_inst_m[1], omega = constants.omega_rps[1], dt = wall_setup.dt_s;
  stepper.set_state(0.03, outward_speed(1.05, 0.03, x_inst, omega), 0.0, 0.0);
  const double t0 = evaluate_instability(constants, stepper, StepReport<double>{}).t_to_instability_s;
  for (int n = 1; n <= 300; ++n) {
    const StepReport<double> rep = stepper.step(0.0, 0.0);
    const InstabilityIndicators<double> ind = evaluate_instability(constants, stepper, rep);
    if (ind.conditions.over_instability_displacement) break;
    CHECK_TRUE(ind.t_valid);
    DOUBLES_EQUAL(t0 - double(n) * dt, ind.t_to_instability_s, 1e-6);
    DOUBLES_EQUAL(1.05, ind.energy_ratio, 1e-9);  // free linear motion with r = 1 conserves the energy
  }
}

TEST(InstabilityIndicators, BelowTheBarrierThereIsNoPredictionAndTheWallTurnsBack) {
  const double x_inst = constants.x_inst_m[1], omega = constants.omega_rps[1];
  for (const double rho : {0.5, 0.99, 0.9995}) {
    stepper.set_state(0.02, outward_speed(rho, 0.02, x_inst, omega), 0.0, 0.0);
    InstabilityIndicators<double> ind = evaluate_instability(constants, stepper, StepReport<double>{});
    DOUBLES_EQUAL(rho, ind.energy_ratio, 1e-9);
    CHECK_FALSE(ind.t_valid);
    CHECK_FALSE(ind.conditions.energy_over_barrier_outward);
    double max_abs_x = 0.0;
    for (int n = 0; n < 3000; ++n) {
      const StepReport<double> rep = stepper.step(0.0, 0.0);
      CHECK_FALSE(rep.exceeded);
      max_abs_x = std::fmax(max_abs_x, std::fabs(stepper.state().x_m));
      ind = evaluate_instability(constants, stepper, rep);
      CHECK_FALSE(ind.t_valid);
      CHECK_FALSE(ind.conditions.energy_over_barrier_outward);
    }
    CHECK_TRUE(max_abs_x < x_inst);
  }
}

TEST(InstabilityIndicators, AboveTheBarrierMovingInwardThereIsNoPrediction) {
  const double x_inst = constants.x_inst_m[1], omega = constants.omega_rps[1];
  stepper.set_state(0.05, -outward_speed(1.5, 0.05, x_inst, omega), 0.0, 0.0);
  const InstabilityIndicators<double> ind = evaluate_instability(constants, stepper, StepReport<double>{});
  DOUBLES_EQUAL(1.5, ind.energy_ratio, 1e-9);
  CHECK_FALSE(ind.t_valid);
  CHECK_FALSE(ind.conditions.energy_over_barrier_outward);
}

TEST(InstabilityIndicators, EnergyMarginRaisesTheFlagButNotThePrediction) {
  const InstabilityConstants<double> margin =
      make_instability_constants(wall_setup, AlarmSettings{0.4, 1.0, 1.1, 0.0, 0.0});
  const double x_inst = margin.x_inst_m[1], omega = margin.omega_rps[1];
  stepper.set_state(0.02, outward_speed(1.05, 0.02, x_inst, omega), 0.0, 0.0);
  InstabilityIndicators<double> ind = evaluate_instability(margin, stepper, StepReport<double>{});
  CHECK_TRUE(ind.t_valid);
  CHECK_FALSE(ind.conditions.energy_over_barrier_outward);
  stepper.set_state(0.02, outward_speed(1.1, 0.02, x_inst, omega), 0.0, 0.0);
  ind = evaluate_instability(margin, stepper, StepReport<double>{});
  CHECK_TRUE(ind.conditions.energy_over_barrier_outward);
}

TEST(InstabilityIndicators, ImminentHorizonRaisesTheEnergyFlagOnlyWhenXInstIsThatClose) {
  // Default settings (margin 1.5) with a horizon of 0.15 s: above the barrier (ρ 1.1 < 1.5) moving outward, the
  // flag is raised when the predicted time to x_inst is at most the horizon and not earlier; never below the barrier
  // nor moving inward; off (0) it is the margin alone.
  AlarmSettings settings;
  settings.imminent_horizon_s = 0.15;
  const InstabilityConstants<double> h = make_instability_constants(wall_setup, settings);
  const InstabilityConstants<double> off =
      make_instability_constants(wall_setup, AlarmSettings{0.4, 1.0, 1.5, 0.0, 0.0});
  DOUBLES_EQUAL(0.15, h.horizon_s, 0.0);
  DOUBLES_EQUAL(0.0, off.horizon_s, 0.0);
  const double x_inst = h.x_inst_m[1], omega = h.omega_rps[1];
  for (const double sign : {1.0, -1.0}) {
    int raised = 0;
    for (const double x_abs : {0.02, 0.05, 0.07, 0.085, 0.095}) {
      stepper.set_state(sign * x_abs, sign * outward_speed(1.1, x_abs, x_inst, omega), 0.0, 0.0);
      const InstabilityIndicators<double> ind = evaluate_instability(h, stepper, StepReport<double>{});
      CHECK_TRUE(ind.t_valid);
      CHECK_EQUAL(ind.t_to_instability_s <= 0.15, ind.conditions.energy_over_barrier_outward);
      raised += ind.conditions.energy_over_barrier_outward ? 1 : 0;
      CHECK_FALSE(evaluate_instability(off, stepper, StepReport<double>{}).conditions.energy_over_barrier_outward);
      stepper.set_state(sign * x_abs, -sign * outward_speed(1.1, x_abs, x_inst, omega), 0.0, 0.0);  // inward
      CHECK_FALSE(evaluate_instability(h, stepper, StepReport<double>{}).conditions.energy_over_barrier_outward);
      stepper.set_state(sign * x_abs, sign * outward_speed(0.99, x_abs, x_inst, omega), 0.0, 0.0);  // below
      CHECK_FALSE(evaluate_instability(h, stepper, StepReport<double>{}).conditions.energy_over_barrier_outward);
    }
    CHECK(raised >= 1 && raised <= 4);  // near x_inst only
  }
  AlarmSettings bad;
  bad.imminent_horizon_s = -0.1;
  CHECK_FALSE(alarm_settings_valid(bad));
  bad.imminent_horizon_s = 10.5;
  CHECK_FALSE(alarm_settings_valid(bad));
}

TEST(InstabilityIndicators, EnergyMinXKeepsTheMarginsRuleFromTheVertical) {
  // energy_min_x 0.5 (issue 40, SPEC §11): with ρ = 2 (over the margin 1.5) moving outward, the flag is raised only
  // from |x| ≥ 0.5 x_inst (the default since 2026-12-01), on both sides; at 0 everywhere; the displacement's own
  // rule (|x| ≥ x_inst) and the horizon rule are not gated. Out of [0, 1] the settings are invalid.
  AlarmSettings settings;
  settings.energy_min_x = 0.5;
  settings.imminent_horizon_s = 0.0;  // the horizon's own flag (not gated) would fire near x_inst at ρ = 2
  const InstabilityConstants<double> g = make_instability_constants(wall_setup, settings);
  const double x_inst = g.x_inst_m[1], omega = g.omega_rps[1];
  DOUBLES_EQUAL(0.5 * x_inst, g.x_energy_min_m[1], 1e-15);
  DOUBLES_EQUAL(0.5 * g.x_inst_m[0], g.x_energy_min_m[0], 1e-15);
  DOUBLES_EQUAL(0.0, constants.x_energy_min_m[1], 0.0);
  for (const double sign : {1.0, -1.0}) {
    for (const double f : {0.0, 0.2, 0.45, 0.499, 0.5, 0.501, 0.7, 0.95}) {
      const double x_abs = f * x_inst;
      stepper.set_state(sign * x_abs, sign * outward_speed(2.0, x_abs, x_inst, omega), 0.0, 0.0);
      const InstabilityIndicators<double> ind = evaluate_instability(g, stepper, StepReport<double>{});
      DOUBLES_EQUAL(2.0, ind.energy_ratio, 1e-9);
      CHECK_EQUAL(f >= 0.5, ind.conditions.energy_over_barrier_outward);
      CHECK_TRUE(ind.t_valid);  // the prediction is not gated
      CHECK_TRUE(evaluate_instability(constants, stepper, StepReport<double>{}).conditions.energy_over_barrier_outward);
    }
  }
  // The horizon rule near x_inst stays: ρ 1.1 < 1.5 at 0.3 x_inst is raised by a 10 s horizon whatever energy_min_x.
  settings.imminent_horizon_s = 10.0;
  const InstabilityConstants<double> gh = make_instability_constants(wall_setup, settings);
  stepper.set_state(0.3 * x_inst, outward_speed(1.1, 0.3 * x_inst, x_inst, omega), 0.0, 0.0);
  CHECK_TRUE(evaluate_instability(gh, stepper, StepReport<double>{}).conditions.energy_over_barrier_outward);
  AlarmSettings bad;
  bad.energy_min_x = -0.01;
  CHECK_FALSE(alarm_settings_valid(bad));
  bad.energy_min_x = 1.01;
  CHECK_FALSE(alarm_settings_valid(bad));
  bad.energy_min_x = 1.0;
  CHECK_TRUE(alarm_settings_valid(bad));
}

TEST(InstabilityIndicators, PredictionIsCappedAtTMax) {
  InstabilityConstants<double> capped = constants;
  capped.t_max_s = 0.25;
  const double x_inst = capped.x_inst_m[1], omega = capped.omega_rps[1];
  stepper.set_state(0.0, outward_speed(1.0001, 0.0, x_inst, omega), 0.0, 0.0);  // about 1.4 s away
  const InstabilityIndicators<double> ind = evaluate_instability(capped, stepper, StepReport<double>{});
  CHECK_TRUE(ind.t_valid);
  DOUBLES_EQUAL(0.25, ind.t_to_instability_s, 0.0);
  CHECK_TRUE(evaluate_instability(constants, stepper, StepReport<double>{}).t_to_instability_s > 1.0);
}

TEST(InstabilityIndicators, CollapseSetsTheCollapseCondition) {
  const StepperSetup<double> s = paper_setup(0.005, ModelKind::linear, 1.2);
  stepper.init(s);
  const InstabilityConstants<double> c = make_instability_constants(s, kMarginOnly);
  stepper.set_state(0.05, outward_speed(1.3, 0.05, c.x_inst_m[1], c.omega_rps[1]), 0.0, 0.0);
  InstabilityAlarm alarm = make_alarm(hold_samples(AlarmSettings{0.4, 1.0, 1.0}, s.dt_s));
  AlarmLevel highest = AlarmLevel::quiet;
  bool imminent_before_collapse = false;
  for (int n = 0; n < 2000 && !stepper.collapsed(); ++n) {
    const StepReport<double> rep = stepper.step(0.0, 0.0);
    const InstabilityIndicators<double> ind = evaluate_instability(c, stepper, rep);
    CHECK_EQUAL(rep.collapsed, ind.conditions.over_collapse_displacement);
    const AlarmUpdate u = alarm.update(ind.conditions);
    if (!rep.collapsed && u.level == AlarmLevel::imminent) imminent_before_collapse = true;
    if (u.level > highest) highest = u.level;
  }
  CHECK_TRUE(stepper.collapsed());
  CHECK_TRUE(imminent_before_collapse);
  CHECK_TRUE(highest == AlarmLevel::collapsed);
}

TEST(InstabilityIndicators, EnergyFlagRaisesImminentBeforeTheWarningDisplacement) {
  // A fast wall near the vertical: IMMINENT by energy at the first step, long before |x| reaches λ_w·x_inst.
  const double x_inst = constants.x_inst_m[1], omega = constants.omega_rps[1];
  stepper.set_state(0.005, outward_speed(1.02, 0.005, x_inst, omega), 0.0, 0.0);
  InstabilityAlarm alarm = make_alarm(1000);
  const StepReport<double> rep = stepper.step(0.0, 0.0);
  const InstabilityIndicators<double> ind = evaluate_instability(constants, stepper, rep);
  CHECK_FALSE(ind.conditions.over_warning_displacement);
  CHECK_TRUE(alarm.update(ind.conditions).level == AlarmLevel::imminent);
}

TEST(InstabilityIndicators, FloatAgreesWithDouble) {
  const StepperSetup<float> sf = cast_setup<float>(wall_setup);
  const InstabilityConstants<float> cf = cast_instability_constants<float>(constants);
  RockingStepper<float> s32;
  s32.init(sf);
  const double x_inst = constants.x_inst_m[1], omega = constants.omega_rps[1];
  const double v0 = outward_speed(1.1, 0.03, x_inst, omega);
  s32.set_state(0.03f, static_cast<float>(v0), 0.0f, 0.0f);
  stepper.set_state(0.03, v0, 0.0, 0.0);
  const InstabilityIndicators<float> f = evaluate_instability(cf, s32, StepReport<float>{});
  const InstabilityIndicators<double> d = evaluate_instability(constants, stepper, StepReport<double>{});
  CHECK_TRUE(f.t_valid);
  DOUBLES_EQUAL(d.energy_ratio, double(f.energy_ratio), 1e-5);
  DOUBLES_EQUAL(d.t_to_instability_s, double(f.t_to_instability_s), 1e-5);
  CHECK_EQUAL(d.conditions.energy_over_barrier_outward, f.conditions.energy_over_barrier_outward);
}
