// The real-time engine: the linear two-block rocking model (SPEC §1–4) in fixed point, with the same algorithm
// as RockingStepper<double> — Newmark (β = 1/4, γ = 1/2), input linear inside the step, start at the threshold,
// impacts and collapse located inside the step, rest after an impact — with the work of a sample bounded: each
// event located by a fixed number of Newton iterations that always run, and a per-sample budget of segments shared by
// the sample's sub-steps (FixedEventBudget, StepperAlarmChain).
//
// Formats: 64-bit state and coefficients (Fixed64, exact 128-bit intermediates); docs/FIXED_POINT.md gives the
// ranges measured over the shipped suite and the real records, and what saturates first:
//   accelerations ü, v̈, G, ẍ, f     AccelQ7_56        ±128 m/s²,    1.4e-17 m/s²
//   displacement x, levels           LengthQ1_62       ±2 m,         2.2e-19 m
//   velocity ẋ                       SpeedQ3_60        ±8 m/s,       8.7e-19 m/s
//   step length h, H                 DurationQ0_63     ±1 s,         1.1e-19 s
//   H²/4                             Duration2Qm12_75  ±2.4e-4 s²,   2.6e-23 s² (steps up to 31 ms)
//   stiffness k = p4/p1              StiffQ8_55        ±256 1/s²,    2.8e-17 1/s²
//   gains F_g, F_u [-], K_g, K_u [1/m] GainQ4_59       ±16,          1.7e-18
//   fractions of a step, √r, D       FractionQ1_62     ±2,           2.2e-19
// The 32-bit formats below (Q7.24, Q1.30, Q3.28) are for sensors, messages and the alarm's indicators.
// The equation is divided through by p1 at initialisation (p1 is constant in the linear model):
//   ẍ = f − k x,  f = p6/p1 = −s(F_fp,s + F_g G) − F_u ü,  k = p4/p1 = K_fp,s + K_g G + s K_u ü.
//
// Why a second stepper and not RockingStepper<Scalar> on a fixed type: RockingStepper's step is a loop of
// advance_segment calls (up to kMaxSegmentsPerStep segments per step, each impact located by regula falsi to
// convergence, up to kRootIterations): data-dependent work, which the firmware cannot have, and iteration counts
// that would differ in fixed point anyway. Changing either stepper to the other's arrangement changes its results,
// and both are pinned bit for bit (golden files, `rockwatch simulate --arith double|fixed`, the monitor). What is
// shared: the model and its set-up (make_stepper_setup in double, StepperSetup, SPEC §1–4), the report's meaning
// (StepReport/FixedStepReport: same fields and fractions of the step), the indicators' definitions and the
// stepper → indicators → alarm composition (stepper_alarm_chain.hpp).
//
// Differences from the double engine, all at the scale of a step and measured in docs/FIXED_POINT.md:
// - at most kMaxSegmentsPerStep segments per step and the sample's budget of further segments (FixedEventBudget):
//   beyond them the wall is put at rest (`rest_forced`): impacts that close together mean settling speeds; the
//   double engine allows 64 segments per step.
// - the event is located by kLocateIterations Newton steps on the exact Newmark residual (a cubic in the
//   sub-step), from the secant; the double engine iterates to convergence.
#pragma once

#include <cstdint>

#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point64.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

namespace rockwatch::core {

// 32-bit formats of the same quantities, for sensors, messages and the alarm's indicators.
using AccelQ7_24 = Fixed<7, 24>;
using LengthQ1_30 = Fixed<1, 30>;
using SpeedQ3_28 = Fixed<3, 28>;
using FractionQ1_30 = Fixed<1, 30>;

// The engine's 64-bit formats.
using AccelQ7_56 = Fixed64<7, 56>;
using LengthQ1_62 = Fixed64<1, 62>;
using SpeedQ3_60 = Fixed64<3, 60>;
using DurationQ0_63 = Fixed64<0, 63>;
using Duration2Qm12_75 = Fixed64<-12, 75>;
using StiffQ8_55 = Fixed64<8, 55>;
using GainQ4_59 = Fixed64<4, 59>;
using FractionQ1_62 = Fixed64<1, 62>;

// Why a fixed-point setup was refused. Values are stable: append, never renumber.
enum class FixedSetupError : std::uint8_t {
  ok = 0,
  model_not_linear = 1,         // the fixed-point engine runs the linear model only
  step_out_of_range = 2,        // dt must be in (0, 0.03] s
  collapse_out_of_range = 3,    // κ·x_inst must stay below 1.9 m (LengthQ1_62)
  constant_out_of_range = 4,    // a model constant does not fit its format (wall far outside masonry sizes)
  gravity_out_of_range = 5,     // g must be below 100 m/s²
  restitution_out_of_range = 6, // r must be in [0, 1]
};

inline const char* fixed_setup_error_message(FixedSetupError e) {
  switch (e) {
    case FixedSetupError::ok: return "ok";
    case FixedSetupError::model_not_linear: return "fixed-point arithmetic supports the linear model only";
    case FixedSetupError::step_out_of_range: return "integration step must be in (0, 0.03] s for fixed point";
    case FixedSetupError::collapse_out_of_range:
      return "kappa * x_inst must be below 1.9 m (fixed-point displacement range +-2 m)";
    case FixedSetupError::constant_out_of_range:
      return "a model constant is outside its fixed-point format (see docs/FIXED_POINT.md)";
    case FixedSetupError::gravity_out_of_range: return "g must be below 100 m/s2 for fixed point";
    case FixedSetupError::restitution_out_of_range: return "r must be in [0, 1]";
  }
  return "?";
}

struct FixedStepperSetup {
  AccelQ7_56 f_fp_mps2[2];    // Fp term of f per side (index side_index) [m/s²]
  GainQ4_59 f_g;              // c6_g/p1 [-]
  GainQ4_59 f_u;              // c6_u/p1 [-]
  StiffQ8_55 k_fp_ps2[2];     // Fp term of k per side [1/s²]
  GainQ4_59 k_g_pm;           // c4_g/p1 [1/m]
  GainQ4_59 k_u_pm;           // c4_u/p1 [1/m]
  AccelQ7_56 g_mps2;          // gravity [m/s²]
  DurationQ0_63 dt_s;         // step [s]
  FractionQ1_62 sqrt_r;       // velocity ratio at impact [-]
  LengthQ1_62 x_inst_m[2];    // per side [m]
  LengthQ1_62 x_collapse_m[2];  // κ·x_inst per side [m]
  SpeedQ3_60 v_rest_mps;      // rest threshold after an impact [m/s]
  SpeedQ3_60 v_count_mps;     // impact-count threshold [m/s]
};

// Initialisation-time conversion from the double setup (all floating point happens here).
inline FixedSetupError make_fixed_setup(const StepperSetup<double>& s, FixedStepperSetup& out) {
  const ModelConstants<double>& c = s.model;
  if (c.kind != ModelKind::linear) return FixedSetupError::model_not_linear;
  if (!(s.dt_s > 0.0 && s.dt_s <= 0.03)) return FixedSetupError::step_out_of_range;
  if (!(s.g_mps2 > 0.0 && s.g_mps2 < 100.0)) return FixedSetupError::gravity_out_of_range;
  if (!(s.sqrt_r >= 0.0 && s.sqrt_r <= 1.0)) return FixedSetupError::restitution_out_of_range;
  for (int i = 0; i < 2; ++i) {
    if (!(s.x_collapse_m[i] < 1.9 && s.x_inst_m[i] > 0.0)) return FixedSetupError::collapse_out_of_range;
  }
  // Each constant must sit well inside its format so that sums with the input stay in range.
  auto fits = [](double v, double range) { return v == v && v > -0.5 * range && v < 0.5 * range; };
  const double p1 = c.c1;
  const double f_g = c.c6_g / p1, f_u = c.c6_u / p1, k_g = c.c4_g / p1, k_u = c.c4_u / p1;
  bool ok = fits(f_g, 16.0) && fits(f_u, 16.0) && fits(k_g, 16.0) && fits(k_u, 16.0);
  for (int i = 0; i < 2; ++i) {
    const double f_fp = c.c6_fp[i] / p1, k_fp = c.c4_fp[i] / p1;
    ok = ok && fits(f_fp, 128.0) && fits(k_fp, 256.0) && fits(k_fp + k_g * s.g_mps2, 256.0) &&
         fits(f_fp + f_g * s.g_mps2, 128.0);
    out.f_fp_mps2[i] = AccelQ7_56(f_fp);
    out.k_fp_ps2[i] = StiffQ8_55(k_fp);
    out.x_inst_m[i] = LengthQ1_62(s.x_inst_m[i]);
    out.x_collapse_m[i] = LengthQ1_62(s.x_collapse_m[i]);
  }
  if (!ok) return FixedSetupError::constant_out_of_range;
  out.f_g = GainQ4_59(f_g);
  out.f_u = GainQ4_59(f_u);
  out.k_g_pm = GainQ4_59(k_g);
  out.k_u_pm = GainQ4_59(k_u);
  out.g_mps2 = AccelQ7_56(s.g_mps2);
  out.dt_s = DurationQ0_63(s.dt_s);
  out.sqrt_r = FractionQ1_62(s.sqrt_r);
  out.v_rest_mps = SpeedQ3_60(s.v_rest_mps);
  out.v_count_mps = SpeedQ3_60(s.v_count_mps);
  return FixedSetupError::ok;
}

// What happened inside one step (fractions of the step in [0, 1]); mirrors StepReport.
struct FixedStepReport {
  bool input_invalid = false;      // G = g + v̈ ≤ 0 at the step end: outside the model, state held
  bool started = false;            // rocking started from rest in this step
  FractionQ1_62 start_fraction{};
  std::uint16_t impacts_counted = 0;  // impacts with |ẋ⁻| ≥ v_count (at most kMaxSegmentsPerStep − 1 per step)
  std::uint16_t impacts_total = 0;    // all impacts
  FractionQ1_62 first_impact_fraction{};
  SpeedQ3_60 first_impact_v_before_mps{};
  SpeedQ3_60 first_impact_v_after_mps{};  // 0 when put at rest (StepReport keeps √r·ẋ⁻ there: a known difference)
  bool came_to_rest = false;
  bool rest_forced = false;        // a second crossing in the step: put at rest without locating it
  bool exceeded = false;           // |x| rose through x_inst in this step
  FractionQ1_62 exceed_fraction{};
  bool collapsed = false;          // |x| reached κ·x_inst; the stepper stops
  FractionQ1_62 collapse_fraction{};
  bool saturated = false;          // a state quantity reached the end of its format: results unreliable
  // Work done, for the constant-iteration proofs and worst-case accounting (tests/sim/test_fixed_engine.cpp):
  std::uint16_t segments = 0;           // trials to the step end (≤ kMaxSegmentsPerStep)
  std::uint16_t events_located = 0;     // impacts, collapse and x_inst passages located inside the step
  std::uint16_t locate_iterations = 0;  // always events_located · kLocateIterations
};

// The work one sample may spend on events, shared by its sub-steps (StepperAlarmChain passes one per sample): what
// bounds the worst sample. Each sub-step's first segment is free; a further segment of the same sub-step (after an
// impact or a start) takes one `extra_segments`. Spent: a sub-step that would need another segment puts the wall at
// rest (`rest_forced`: impacts that close together mean settling speeds).
struct FixedEventBudget {
  int extra_segments = 0;
};

class FixedRockingStepper {
 public:
  // Newton iterations on the event residual, always all of them for a located event (constant work per event). 8
  // keep the default study's agreement with the double engine (recall 1.0, verdicts 99.94 %); 4 and 6 lose it
  // (docs/BENCHMARKS.md, "Sub-steps, the worst sample and the alarm"). Was 12.
  static constexpr int kLocateIterations = 8;
  // Segments (impacts + 1) handled inside one step; more means settling speeds and the wall is put at rest.
  static constexpr int kMaxSegmentsPerStep = 16;
  // The event budget of one sample (StepperAlarmChain), whatever its number of sub-steps: 32 further segments, which
  // bounds a sample of settling chatter (impacts microseconds apart) at 5 + 32 segments instead of 5 × 16 at 200 Hz.
  // Tighter budgets, or events beyond a budget located with fewer iterations, cost the agreement with the double
  // engine (measured in docs/BENCHMARKS.md); a cheaper location for chatter is what would allow them.
  static constexpr FixedEventBudget kSampleBudget{32};

  FixedSetupError init(const StepperSetup<double>& setup) {
    const FixedSetupError e = make_fixed_setup(setup, setup_);
    reset(AccelQ7_56{}, AccelQ7_56{});
    return e;
  }

  // Wall at rest, vertical, with the given input at the current instant.
  void reset(AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2) {
    x_ = LengthQ1_62{};
    xd_ = SpeedQ3_60{};
    xdd_ = AccelQ7_56{};
    side_ = Side::positive;
    moving_ = false;
    collapsed_ = false;
    coefficients(ug_mps2, vg_mps2, f_prev_, k_prev_);
  }

  // Places the wall in motion (tests, restarts). Side follows x, or ẋ when x = 0.
  void set_state(LengthQ1_62 x_m, SpeedQ3_60 xd_mps, AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2) {
    reset(ug_mps2, vg_mps2);
    x_ = x_m;
    xd_ = xd_mps;
    if (x_m != LengthQ1_62{}) {
      side_ = x_m > LengthQ1_62{} ? Side::positive : Side::negative;
    } else {
      side_ = xd_mps < SpeedQ3_60{} ? Side::negative : Side::positive;
    }
    moving_ = x_m != LengthQ1_62{} || xd_mps != SpeedQ3_60{};
    const int i = side_index(side_);
    xdd_ = f_prev_[i] - wide_mul<AccelQ7_56>(k_prev_[i], x_);
  }

  // Advances one step of setup dt to the given input at the step end, with a budget of its own (kSampleBudget).
  FixedStepReport step(AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2) {
    FixedEventBudget budget = kSampleBudget;
    return step(ug_mps2, vg_mps2, budget);
  }

  // The same, spending from a budget shared with the other sub-steps of the sample (FixedEventBudget).
  FixedStepReport step(AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2, FixedEventBudget& budget) {
    FixedStepReport report;
    AccelQ7_56 f_end[2];
    StiffQ8_55 k_end[2];
    const bool valid = coefficients(ug_mps2, vg_mps2, f_end, k_end);
    if (collapsed_ || !valid) {
      report.input_invalid = !valid;
      keep_coefficients(f_end, k_end);
      return report;
    }
    MotionPoint at{x_, xd_, xdd_, FractionQ1_62{}, side_};
    bool finished = false;
    for (int segment = 0; segment < kMaxSegmentsPerStep && !finished; ++segment) {
      if (segment > 0) {
        if (budget.extra_segments <= 0) break;
        --budget.extra_segments;
      }
      if (!moving_ && !try_start(f_end, at, report)) break;
      finished = advance_segment(f_end, k_end, at, report);
    }
    if (!finished && moving_) {
      // Impacts closer together than a step / kMaxSegmentsPerStep: settling speeds. Rest; the start logic
      // takes over if the ground drives the wall out.
      put_at_rest();
      report.came_to_rest = true;
      report.rest_forced = true;
    }
    report.saturated = x_.saturated() || xd_.saturated() || xdd_.saturated();
    keep_coefficients(f_end, k_end);
    return report;
  }

  // The velocity ratio at impact √r from now on (the observer's estimate of the real wall's restitution).
  void set_sqrt_r(FractionQ1_62 sqrt_r) { setup_.sqrt_r = sqrt_r; }

  LengthQ1_62 x_m() const { return x_; }
  SpeedQ3_60 xd_mps() const { return xd_; }
  AccelQ7_56 xdd_mps2() const { return xdd_; }
  Side side() const { return side_; }
  bool moving() const { return moving_; }
  bool collapsed() const { return collapsed_; }
  const FixedStepperSetup& setup() const { return setup_; }

 private:
  // A state inside the current step: θ is the fraction of the step already done.
  struct MotionPoint {
    LengthQ1_62 x_m;
    SpeedQ3_60 xd_mps;
    AccelQ7_56 xdd_mps2;
    FractionQ1_62 theta;
    Side side;
  };
  struct Trial {
    LengthQ1_62 x_m;
    SpeedQ3_60 xd_mps;
    AccelQ7_56 xdd_mps2;
  };
  // The rest of the step from a point, on its side: length, and f, k at its start and their change to its end.
  struct SubStep {
    DurationQ0_63 h_s;           // H_r = (1 − θ)·dt
    Duration2Qm12_75 quarter_h2;  // H_r²/4
    AccelQ7_56 f_start, f_delta;
    StiffQ8_55 k_start, k_delta;
  };

  // At rest from `at.theta`: if s·f rises above zero before the step end (input linear in time, so s·f is affine
  // in θ), start rocking towards s at the crossing. Returns true if moving.
  bool try_start(const AccelQ7_56 f_end[2], MotionPoint& at, FixedStepReport& report) {
    for (int candidate = 0; candidate < 2; ++candidate) {
      const Side s = candidate == 0 ? Side::positive : Side::negative;
      const int i = side_index(s);
      const AccelQ7_56 drive_end = s == Side::positive ? f_end[i] : -f_end[i];
      if (!(drive_end > AccelQ7_56{})) continue;
      const AccelQ7_56 f_now = f_at(f_end, s, at.theta);
      const AccelQ7_56 drive_now = s == Side::positive ? f_now : -f_now;
      FractionQ1_62 theta = at.theta;
      if (drive_now < AccelQ7_56{}) {
        theta = theta + wide_mul<FractionQ1_62>(FractionQ1_62(1) - theta,
                                                 wide_div<FractionQ1_62>(-drive_now, drive_end - drive_now));
      }
      at = MotionPoint{LengthQ1_62{}, SpeedQ3_60{}, f_at(f_end, s, theta), theta, s};
      x_ = LengthQ1_62{};
      xd_ = SpeedQ3_60{};
      xdd_ = at.xdd_mps2;
      side_ = s;
      moving_ = true;
      if (!report.started) {
        report.started = true;
        report.start_fraction = theta;
      }
      return true;
    }
    return false;
  }

  // From `at` to the step end on its side, stopping at the first impact or at collapse. Returns true when the
  // step is finished (end reached, collapsed or at rest), false after an impact that leaves the wall moving.
  bool advance_segment(const AccelQ7_56 f_end[2], const StiffQ8_55 k_end[2], MotionPoint& at,
                       FixedStepReport& report) {
    ++report.segments;
    const SubStep whole = sub_step(at, f_end, k_end);
    const Trial end = trial(at, whole, FractionQ1_62(1));
    const int si = side_index(at.side);
    const LengthQ1_62 x0 = signed_x(at.side, at.x_m), x1 = signed_x(at.side, end.x_m);
    const bool on_hinge_inward = x0 == LengthQ1_62{} && signed_v(at.side, at.xd_mps) < SpeedQ3_60{};
    if (x1 < LengthQ1_62{} || on_hinge_inward) {
      const FractionQ1_62 tau = on_hinge_inward ? FractionQ1_62{} : locate(at, whole, LengthQ1_62{}, report);
      const Trial event = trial(at, whole, tau);
      const FractionQ1_62 theta = at.theta + wide_mul<FractionQ1_62>(tau, FractionQ1_62(1) - at.theta);
      const SpeedQ3_60 v_before = on_hinge_inward ? at.xd_mps : event.xd_mps;
      const SpeedQ3_60 v_after = wide_mul<SpeedQ3_60>(setup_.sqrt_r, v_before);
      if (report.impacts_total == 0) {
        report.first_impact_fraction = theta;
        report.first_impact_v_before_mps = v_before;
        report.first_impact_v_after_mps = v_after;
      }
      ++report.impacts_total;
      if (abs(v_before) >= setup_.v_count_mps) ++report.impacts_counted;
      const Side s = opposite(at.side);
      at = MotionPoint{LengthQ1_62{}, v_after, f_at(f_end, s, theta), theta, s};
      x_ = LengthQ1_62{};
      xd_ = v_after;
      xdd_ = at.xdd_mps2;
      side_ = s;
      const AccelQ7_56 drive = s == Side::positive ? at.xdd_mps2 : -at.xdd_mps2;
      if (abs(v_after) < setup_.v_rest_mps && !(drive > AccelQ7_56{})) {
        put_at_rest();
        report.came_to_rest = true;
        if (report.impacts_total == 1) report.first_impact_v_after_mps = SpeedQ3_60{};
      }
      return false;
    }
    const LengthQ1_62 inst = setup_.x_inst_m[si];
    const LengthQ1_62 limit = setup_.x_collapse_m[si];
    if (x0 < inst && x1 >= inst && !report.exceeded) {
      report.exceeded = true;
      const FractionQ1_62 tau = locate(at, whole, inst, report);
      report.exceed_fraction = at.theta + wide_mul<FractionQ1_62>(tau, FractionQ1_62(1) - at.theta);
    }
    if (x1 >= limit) {
      const FractionQ1_62 tau = locate(at, whole, limit, report);
      const Trial event = trial(at, whole, tau);
      x_ = at.side == Side::positive ? limit : -limit;
      xd_ = event.xd_mps;
      xdd_ = event.xdd_mps2;
      moving_ = false;
      collapsed_ = true;
      report.collapsed = true;
      report.collapse_fraction = at.theta + wide_mul<FractionQ1_62>(tau, FractionQ1_62(1) - at.theta);
      return true;
    }
    x_ = end.x_m;
    xd_ = end.xd_mps;
    xdd_ = end.xdd_mps2;
    side_ = at.side;
    return true;
  }

  void put_at_rest() {
    x_ = LengthQ1_62{};
    xd_ = SpeedQ3_60{};
    xdd_ = AccelQ7_56{};
    moving_ = false;
  }

  static LengthQ1_62 signed_x(Side s, LengthQ1_62 x) { return s == Side::positive ? x : -x; }
  static SpeedQ3_60 signed_v(Side s, SpeedQ3_60 v) { return s == Side::positive ? v : -v; }

  // f and k of both sides for an input; false when G = g + v̈ ≤ 0.
  // Scaling and overflow: products of GainQ4_59 by AccelQ7_56 (|G| < 256 with g < 100 and |v̈| < 128) stay
  // below 16·256 before narrowing; the sums saturate (flagged through the state) only for |ü| beyond ~80 m/s².
  bool coefficients(AccelQ7_56 ug, AccelQ7_56 vg, AccelQ7_56 f[2], StiffQ8_55 k[2]) const {
    const AccelQ7_56 gravity = setup_.g_mps2 + vg;
    const AccelQ7_56 f_gravity = wide_mul<AccelQ7_56>(setup_.f_g, gravity);
    const AccelQ7_56 f_push = wide_mul<AccelQ7_56>(setup_.f_u, ug);
    const StiffQ8_55 k_gravity = wide_mul<StiffQ8_55>(setup_.k_g_pm, gravity);
    const StiffQ8_55 k_push = wide_mul<StiffQ8_55>(setup_.k_u_pm, ug);
    for (int i = 0; i < 2; ++i) {
      const AccelQ7_56 restoring = setup_.f_fp_mps2[i] + f_gravity;
      f[i] = (i == 1 ? -restoring : restoring) - f_push;
      k[i] = setup_.k_fp_ps2[i] + k_gravity + (i == 1 ? k_push : -k_push);
    }
    return gravity > AccelQ7_56{};
  }

  void keep_coefficients(const AccelQ7_56 f[2], const StiffQ8_55 k[2]) {
    for (int i = 0; i < 2; ++i) {
      f_prev_[i] = f[i];
      k_prev_[i] = k[i];
    }
  }

  // f on side s at fraction θ of the step (input linear in time).
  AccelQ7_56 f_at(const AccelQ7_56 f_end[2], Side s, FractionQ1_62 theta) const {
    const int i = side_index(s);
    return f_prev_[i] + wide_mul<AccelQ7_56>(theta, f_end[i] - f_prev_[i]);
  }

  SubStep sub_step(const MotionPoint& p, const AccelQ7_56 f_end[2], const StiffQ8_55 k_end[2]) const {
    const int i = side_index(p.side);
    SubStep s;
    s.h_s = wide_mul<DurationQ0_63>(FractionQ1_62(1) - p.theta, setup_.dt_s);
    s.quarter_h2 = Duration2Qm12_75::from_raw(fixed64_detail::mul_round(s.h_s.raw(), s.h_s.raw(), 2 * 63 + 2 - 75));
    s.f_start = f_at(f_end, p.side, p.theta);
    s.f_delta = f_end[i] - s.f_start;
    s.k_start = k_start_at(k_end, i, p.theta);
    s.k_delta = k_end[i] - s.k_start;
    return s;
  }

  StiffQ8_55 k_start_at(const StiffQ8_55 k_end[2], int i, FractionQ1_62 theta) const {
    return k_prev_[i] + wide_mul<StiffQ8_55>(theta, k_end[i] - k_prev_[i]);
  }

  // Newmark from p over the fraction τ of its sub-step, with f and k at the sub-step's end.
  // Scaling and overflow: H ẋ < 0.24 m and H²/4 (ẍ₀ + f) < 0.06 m for |ẍ| < 128 and H ≤ 30 ms; D = 1 + H²k/4
  // is within 1 ± 0.06 for |k| < 256, so x₁ = N/D saturates only when the wall is far beyond collapse.
  Trial trial(const MotionPoint& p, const SubStep& s, FractionQ1_62 tau) const {
    const DurationQ0_63 h = wide_mul<DurationQ0_63>(tau, s.h_s);
    const Duration2Qm12_75 quarter_h2 = Duration2Qm12_75::from_raw(fixed64_detail::mul_round(h.raw(), h.raw(), 2 * 63 + 2 - 75));
    const AccelQ7_56 f = s.f_start + wide_mul<AccelQ7_56>(tau, s.f_delta);
    const StiffQ8_55 k = s.k_start + wide_mul<StiffQ8_55>(tau, s.k_delta);
    const LengthQ1_62 numerator =
        p.x_m + wide_mul<LengthQ1_62>(h, p.xd_mps) + wide_mul<LengthQ1_62>(quarter_h2, p.xdd_mps2 + f);
    const FractionQ1_62 denominator = FractionQ1_62(1) + wide_mul<FractionQ1_62>(quarter_h2, k);
    Trial t;
    t.x_m = wide_div<LengthQ1_62>(numerator, denominator);
    t.xdd_mps2 = f - wide_mul<AccelQ7_56>(k, t.x_m);
    const DurationQ0_63 half_h = DurationQ0_63::from_raw(fixed64_detail::convert_round(h.raw(), 1));
    t.xd_mps = p.xd_mps + wide_mul<SpeedQ3_60>(half_h, p.xdd_mps2 + t.xdd_mps2);
    return t;
  }

  // τ in [0, 1] where the Newmark step from p reaches s·x = level: root of the exact residual
  //   r(τ) = c0 + c1 τ + c2 τ² + c3 τ³  [m],  c0 = s·x₀ − L,  c1 = H s·ẋ₀,  c2 = H²/4 (s·ẍ₀ + s·f₀ − L k₀),
  //   c3 = H²/4 (s·Δf − L Δk)
  // (s times the numerator of x(τ) minus L times its denominator). Secant start from r(0) and r(1), then
  // kLocateIterations Newton steps, each clamped to [0, 1]. Always runs in full.
  // Scaling and overflow: |c0| < 4 m, |c1| < 0.24 m, |c2|, |c3| < 0.06 m for H ≤ 30 ms, so the Horner sums
  // (τ ≤ 1) stay below 2 m; Q1.62 resolves a micrometre-scale residual to 1e-13 of itself. r' → 0 saturates the
  // quotient, which is then clamped to the bracket.
  FractionQ1_62 locate(const MotionPoint& p, const SubStep& s, LengthQ1_62 level, FixedStepReport& report) const {
    ++report.events_located;
    const bool pos = p.side == Side::positive;
    const AccelQ7_56 level_k0 = wide_mul<AccelQ7_56>(s.k_start, level);
    const AccelQ7_56 level_dk = wide_mul<AccelQ7_56>(s.k_delta, level);
    const AccelQ7_56 a2 = (pos ? p.xdd_mps2 + s.f_start : -(p.xdd_mps2 + s.f_start)) - level_k0;
    const AccelQ7_56 a3 = (pos ? s.f_delta : -s.f_delta) - level_dk;
    const LengthQ1_62 c0 = signed_x(p.side, p.x_m) - level;
    const LengthQ1_62 c1 = wide_mul<LengthQ1_62>(s.h_s, signed_v(p.side, p.xd_mps));
    const LengthQ1_62 c2 = wide_mul<LengthQ1_62>(s.quarter_h2, a2);
    const LengthQ1_62 c3 = wide_mul<LengthQ1_62>(s.quarter_h2, a3);
    // A start on the level (on the hinge after a start from rest) has the root τ = 0: divide it out, as the
    // double engine does.
    const bool on_level = c0 == LengthQ1_62{};
    auto value_at = [&](FractionQ1_62 t) {
      const LengthQ1_62 r1 = c1 + wide_mul<LengthQ1_62>(t, c2 + wide_mul<LengthQ1_62>(t, c3));
      return on_level ? r1 : c0 + wide_mul<LengthQ1_62>(t, r1);
    };
    // Newton kept inside a bracket [lo, hi] that holds the root; a step that leaves it falls back to the
    // bracket's Illinois secant (the end kept twice has its value halved), the double engine's method. The
    // response can turn inside a step and touch the level almost tangentially, where Newton alone is slow.
    FractionQ1_62 lo{}, hi(1);
    LengthQ1_62 g_lo = value_at(lo), g_hi = value_at(hi);
    const bool lo_positive = g_lo > LengthQ1_62{};
    int kept = 0;  // −1: lo kept last time, +1: hi kept last time
    FractionQ1_62 tau = clamp_fraction(wide_div<FractionQ1_62>(g_lo, g_lo - g_hi));
    for (int it = 0; it < kLocateIterations; ++it) {
      ++report.locate_iterations;
      const LengthQ1_62 value = value_at(tau);
      const LengthQ1_62 slope =
          on_level ? c2 + wide_mul<LengthQ1_62>(tau, c3 + c3)
                   : c1 + wide_mul<LengthQ1_62>(tau, c2 + c2 + wide_mul<LengthQ1_62>(tau, c3 + c3 + c3));
      if ((value > LengthQ1_62{}) == lo_positive) {
        lo = tau;
        g_lo = value;
        if (kept == 1) g_hi = LengthQ1_62::from_raw(g_hi.raw() / 2);
        kept = 1;
      } else {
        hi = tau;
        g_hi = value;
        if (kept == -1) g_lo = LengthQ1_62::from_raw(g_lo.raw() / 2);
        kept = -1;
      }
      const FractionQ1_62 newton = tau - wide_div<FractionQ1_62>(value, slope);
      if (newton > lo && newton < hi) {
        tau = newton;
      } else {  // the secant's division only when it is used (the same τ; fewer divisions on the M4)
        tau = clamp_to(lo + wide_mul<FractionQ1_62>(hi - lo, wide_div<FractionQ1_62>(g_lo, g_lo - g_hi)), lo, hi);
      }
    }
    return tau;
  }

  static FractionQ1_62 clamp_to(FractionQ1_62 t, FractionQ1_62 lo, FractionQ1_62 hi) {
    if (t < lo) return lo;
    if (t > hi) return hi;
    return t;
  }

  static FractionQ1_62 clamp_fraction(FractionQ1_62 t) {
    if (t < FractionQ1_62{}) return FractionQ1_62{};
    if (t > FractionQ1_62(1)) return FractionQ1_62(1);
    return t;
  }

  FixedStepperSetup setup_{};
  LengthQ1_62 x_{};
  SpeedQ3_60 xd_{};
  AccelQ7_56 xdd_{};
  Side side_ = Side::positive;
  bool moving_ = false;
  bool collapsed_ = false;
  AccelQ7_56 f_prev_[2]{};  // f and k of both sides at the start of the next step
  StiffQ8_55 k_prev_[2]{};
};

}  // namespace rockwatch::core
