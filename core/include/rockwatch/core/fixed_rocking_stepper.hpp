// The real-time engine: the linear two-block rocking model (SPEC §1–4) in fixed point, with the same algorithm
// as RockingStepper<double> — Newmark (β = 1/4, γ = 1/2), input linear inside the step, start at the threshold,
// impacts and collapse located inside the step, rest after an impact, the chatter rule — with the work of a step
// bounded: each event located by a fixed number of Newton iterations that always run, and at most
// kMaxImpactsPerSubstep impacts located per step (the chatter rule of every engine, rocking_segments.hpp).
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
// The segment logic (events, impact and rest rules, the bounds on segments) is the one of every stepper
// (rocking_segments.hpp, shared with RockingStepper<double>); this file is its fixed-point arithmetic. Why not
// RockingStepper<Scalar> on a fixed type: its regula falsi iterates to convergence (data-dependent work, which the
// firmware cannot have, and iteration counts that would differ in fixed point), and its Newmark step goes through the
// full model's coefficients; here the linear equation is divided by p1 once and each event is located by
// kLocateIterations Newton steps on the exact Newmark residual (a cubic in the sub-step), from the secant. Both
// arithmetics are pinned bit for bit (golden files, `rockwatch simulate --arith double|fixed`, the monitor); the
// differences that remain are of arithmetic: events located by a fixed number of Newton steps, where the double engine
// iterates to convergence (measured in docs/FIXED_POINT.md). The chatter rule and its K are the same in both.
#pragma once

#include <cstdint>

#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point64.hpp"
#include "rockwatch/core/rocking_segments.hpp"
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

// What happened inside one step, in the fixed-point formats (fractions of the step in [0, 1]).
using FixedStepReport = StepReport<FractionQ1_62, SpeedQ3_60>;

// The fixed-point formats and bounds of RockingSegments.
struct FixedRockingStepperTypes {
  using Length = LengthQ1_62;
  using Speed = SpeedQ3_60;
  using Accel = AccelQ7_56;
  using Fraction = FractionQ1_62;
  // What each piece of work costs on a Cortex-M4 [instructions], upper bounds measured on the emulated M4
  // (scripts/m4-replay.sh; docs/BENCHMARKS.md, "Bounded work per call"): the meter of a call (core/work_meter.hpp).
  static constexpr WorkCosts kWork{800, 1450, 10000, 1100};
};

class FixedRockingStepper : public RockingSegments<FixedRockingStepper, FixedRockingStepperTypes> {
  using Base = RockingSegments<FixedRockingStepper, FixedRockingStepperTypes>;
  friend Base;

 public:
  using Base::step;
  // Newton iterations on the event residual, always all of them for a located event (constant work per event). 8
  // keep the default study's agreement with the double engine (recall 1.0, verdicts 99.94 %); 4 and 6 lose it
  // (docs/BENCHMARKS.md, "Sub-steps, the worst sample and the alarm"). Was 12.
  static constexpr int kLocateIterations = 8;

  FixedSetupError init(const StepperSetup<double>& setup) {
    const FixedSetupError e = make_fixed_setup(setup, setup_);
    nominal_ = setup_;
    reset(AccelQ7_56{}, AccelQ7_56{});
    return e;
  }

  // Wall at rest, vertical, with the given input at the current instant.
  void reset(AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2) {
    rest_vertical();
    coefficients(ug_mps2, vg_mps2, f_prev_, k_prev_);
    in_step_ = false;  // a step stopped inside (metered) is abandoned
  }

  // Places the wall in motion (tests, restarts). Side follows x, or ẋ when x = 0.
  void set_state(LengthQ1_62 x_m, SpeedQ3_60 xd_mps, AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2) {
    reset(ug_mps2, vg_mps2);
    place(x_m, xd_mps);
    const int i = side_index(side_);
    state_.xdd_mps2 = f_prev_[i] - wide_mul<AccelQ7_56>(k_prev_[i], state_.x_m);
  }

  // set_state() at the input the stepper already holds (the end of its last step, or the last set_state/
  // set_capacity_scales): the same state, without recomputing f and k from it (the observer's corrections).
  void correct_state(LengthQ1_62 x_m, SpeedQ3_60 xd_mps) {
    rest_vertical();
    place(x_m, xd_mps);
    const int i = side_index(side_);
    state_.xdd_mps2 = f_prev_[i] - wide_mul<AccelQ7_56>(k_prev_[i], state_.x_m);
  }

  // The step in pieces paid from a meter (core/work_meter.hpp): begin_step(), then continue_step() until it returns
  // true; step_report() is then the step's report. step(ug, vg) is both at once (RockingSegments).
  void begin_step(AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2) {
    report_ = FixedStepReport{};
    step_valid_ = coefficients(ug_mps2, vg_mps2, f_end_, k_end_);
    begin_segments();
    in_step_ = true;
  }
  template <typename Meter>
  bool continue_step(Meter& meter) {
    if (!collapsed_ && step_valid_) {
      if (!run_segments(meter)) return false;
      report_.saturated = state_.x_m.saturated() || state_.xd_mps.saturated() || state_.xdd_mps2.saturated();
    } else {
      report_.input_invalid = !step_valid_;
    }
    for (int i = 0; i < 2; ++i) {
      f_prev_[i] = f_end_[i];
      k_prev_[i] = k_end_[i];
    }
    in_step_ = false;
    return true;
  }
  // A step begun (begin_step) whose continue_step() has not yet returned true: a metered caller stopped inside it.
  bool step_in_progress() const { return in_step_; }

  // The velocity ratio at impact √r from now on (the observer's estimate of the real wall's restitution).
  void set_sqrt_r(FractionQ1_62 sqrt_r) { setup_.sqrt_r = sqrt_r; }

  // The wall's capacity and stiffness from now on (the observer's estimate, SPEC §9), as RockingStepper's: f's
  // gravity and overburden parts times kc, k's times kk, x_inst and κ·x_inst times kc/kk; (ug, vg) is the current
  // input (the start of the next step's ramp, recomputed with the new constants). Only the observer calls this.
  // Scaling and overflow: the observer keeps kc, kk in [0.25, 4] and kc/kk in [0.3, 2]; masonry walls have |f| and
  // |k| far below a quarter of their formats' ranges (paper wall: 1.7 m/s², 16.5 1/s²); x_collapse·kc/kk beyond
  // ±2 m saturates (flagged through the state like any other saturation).
  void set_capacity_scales(GainQ4_59 kc, GainQ4_59 kk, AccelQ7_56 ug_mps2, AccelQ7_56 vg_mps2) {
    const GainQ4_59 ratio = wide_div<GainQ4_59>(kc, kk);
    for (int i = 0; i < 2; ++i) {
      setup_.f_fp_mps2[i] = wide_mul<AccelQ7_56>(kc, nominal_.f_fp_mps2[i]);
      setup_.k_fp_ps2[i] = wide_mul<StiffQ8_55>(kk, nominal_.k_fp_ps2[i]);
      setup_.x_inst_m[i] = wide_mul<LengthQ1_62>(ratio, nominal_.x_inst_m[i]);
      setup_.x_collapse_m[i] = wide_mul<LengthQ1_62>(ratio, nominal_.x_collapse_m[i]);
    }
    setup_.f_g = wide_mul<GainQ4_59>(kc, nominal_.f_g);
    setup_.k_g_pm = wide_mul<GainQ4_59>(kk, nominal_.k_g_pm);
    coefficients(ug_mps2, vg_mps2, f_prev_, k_prev_);
  }

  LengthQ1_62 x_m() const { return state_.x_m; }
  SpeedQ3_60 xd_mps() const { return state_.xd_mps; }
  AccelQ7_56 xdd_mps2() const { return state_.xdd_mps2; }
  const FixedStepperSetup& setup() const { return setup_; }

 private:
  // The rest of the step from a point, on its side: where it starts, its length, and f, k at its start and their
  // change to its end.
  struct Segment {
    MotionState<LengthQ1_62, SpeedQ3_60, AccelQ7_56> from;
    FractionQ1_62 theta;         // the fraction of the step already done
    Side side;
    DurationQ0_63 h_s;           // H_r = (1 − θ)·dt
    Duration2Qm12_75 quarter_h2;  // H_r²/4
    AccelQ7_56 f_start, f_delta;
    StiffQ8_55 k_start, k_delta;
  };
  using Trial = MotionState<LengthQ1_62, SpeedQ3_60, AccelQ7_56>;
  // An event inside a segment: τ, the fraction of the segment, and θ, of the step.
  struct Located {
    FractionQ1_62 tau;
    FractionQ1_62 theta;
  };

  // s·f at x = 0 at fraction θ of the step: > 0 means the ground drives the wall out towards s (f = p6/p1, p1 > 0).
  AccelQ7_56 drive(Side s, FractionQ1_62 theta) const {
    const AccelQ7_56 f = f_at(s, theta);
    return s == Side::positive ? f : -f;
  }
  AccelQ7_56 drive_at_end(Side s) const {
    const AccelQ7_56 f = f_end_[side_index(s)];
    return s == Side::positive ? f : -f;
  }

  // s·f is affine in θ (input linear in time), so the crossing is exact up to rounding.
  FractionQ1_62 start_crossing(FractionQ1_62 theta, AccelQ7_56 now, AccelQ7_56 end) const {
    return theta + wide_mul<FractionQ1_62>(FractionQ1_62(1) - theta, wide_div<FractionQ1_62>(-now, end - now));
  }

  AccelQ7_56 accel_at_hinge(Side s, FractionQ1_62 theta) const { return f_at(s, theta); }

  SpeedQ3_60 rebound(SpeedQ3_60 v_mps) const { return wide_mul<SpeedQ3_60>(setup_.sqrt_r, v_mps); }

  Segment begin_segment(FractionQ1_62 theta) const {
    const int i = side_index(side_);
    Segment s;
    s.from = state_;
    s.theta = theta;
    s.side = side_;
    s.h_s = wide_mul<DurationQ0_63>(FractionQ1_62(1) - theta, setup_.dt_s);
    s.quarter_h2 = Duration2Qm12_75::from_raw(fixed64_detail::mul_round(s.h_s.raw(), s.h_s.raw(), 2 * 63 + 2 - 75));
    s.f_start = f_at(side_, theta);
    s.f_delta = f_end_[i] - s.f_start;
    s.k_start = k_prev_[i] + wide_mul<StiffQ8_55>(theta, k_end_[i] - k_prev_[i]);
    s.k_delta = k_end_[i] - s.k_start;
    return s;
  }

  Trial end_of(const Segment& s) const { return trial(s, FractionQ1_62(1)); }
  Trial state_at(const Segment& s, Located at) const { return trial(s, at.tau); }

  Located locate(const Segment& s, const Trial&, LengthQ1_62 level, FixedStepReport& report) const {
    const FractionQ1_62 tau = locate_tau(s, level, report);
    return Located{tau, s.theta + wide_mul<FractionQ1_62>(tau, FractionQ1_62(1) - s.theta)};
  }

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

  // f on side s at fraction θ of the step (input linear in time).
  AccelQ7_56 f_at(Side s, FractionQ1_62 theta) const {
    const int i = side_index(s);
    return f_prev_[i] + wide_mul<AccelQ7_56>(theta, f_end_[i] - f_prev_[i]);
  }

  // Newmark from the segment's start over the fraction τ of the segment, with f and k at its end.
  // Scaling and overflow: H ẋ < 0.24 m and H²/4 (ẍ₀ + f) < 0.06 m for |ẍ| < 128 and H ≤ 30 ms; D = 1 + H²k/4
  // is within 1 ± 0.06 for |k| < 256, so x₁ = N/D saturates only when the wall is far beyond collapse.
  Trial trial(const Segment& s, FractionQ1_62 tau) const {
    const Trial& p = s.from;
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
  FractionQ1_62 locate_tau(const Segment& s, LengthQ1_62 level, FixedStepReport& report) const {
    const Trial& p = s.from;
    ++report.events_located;
    const bool pos = s.side == Side::positive;
    const AccelQ7_56 level_k0 = wide_mul<AccelQ7_56>(s.k_start, level);
    const AccelQ7_56 level_dk = wide_mul<AccelQ7_56>(s.k_delta, level);
    const AccelQ7_56 a2 = (pos ? p.xdd_mps2 + s.f_start : -(p.xdd_mps2 + s.f_start)) - level_k0;
    const AccelQ7_56 a3 = (pos ? s.f_delta : -s.f_delta) - level_dk;
    const LengthQ1_62 c0 = signed_x(s.side, p.x_m) - level;
    const LengthQ1_62 c1 = wide_mul<LengthQ1_62>(s.h_s, signed_v(s.side, p.xd_mps));
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
  FixedStepperSetup nominal_{};  // the setup as made by init() (set_capacity_scales scales from it)
  AccelQ7_56 f_prev_[2]{};  // f and k of both sides at the start of the step (the previous input)
  StiffQ8_55 k_prev_[2]{};
  AccelQ7_56 f_end_[2]{};   // and at its end (this step's input)
  StiffQ8_55 k_end_[2]{};
  bool step_valid_ = false;   // its input is inside the model (G > 0)
  bool in_step_ = false;      // begun, continue_step() not yet done (step_in_progress)
};

}  // namespace rockwatch::core
