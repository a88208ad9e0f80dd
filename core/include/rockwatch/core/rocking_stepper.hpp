// The two-block rocking integrator (SPEC §2–4) in floating point: constant step, Newmark with impacts located
// inside the step, start of motion at the threshold, rest logic and collapse located inside the step.
//
// The segment logic (events, impact and rest rules, the bounds on segments) is the one of every stepper
// (rocking_segments.hpp); this file is its floating-point arithmetic: Newmark through the model's coefficients
// (full or linear model), events located by Illinois regula falsi to convergence.
//
// Written for any floating-point Scalar (double; float compiles): no heap, no exceptions, no I/O,
// bounded loops. Inputs are ground accelerations at the step ends; between them the input is linear (SPEC §4).
// Event times are reported as fractions of the current step, so the caller keeps absolute time in whatever
// representation it likes (seconds in double, a sample counter in firmware).
#pragma once

#include <cmath>
#include <cstdint>

#include "rockwatch/core/model.hpp"
#include "rockwatch/core/newmark.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_segments.hpp"
#include "rockwatch/core/wall.hpp"

namespace rockwatch::core {

// Everything the stepper needs, prepared once in double (see make_stepper_setup) and cast to Scalar.
template <typename Scalar>
struct StepperSetup {
  ModelConstants<Scalar> model;
  Scalar g_mps2;          // gravity [m/s²]
  Scalar dt_s;            // constant step [s]
  Scalar sqrt_r;          // velocity ratio at impact √r [-]
  Scalar x_inst_m[2];     // static instability displacement per side (index side_index) [m]
  Scalar x_collapse_m[2]; // κ·x_inst per side [m]
  Scalar v_rest_mps;      // put at rest after an impact when |ẋ⁺| is below this [m/s]
  Scalar v_count_mps;     // count an impact when |ẋ⁻| is at least this [m/s]
};

struct StepperOptions {
  double dt_s = 0.005;        // integration step [s]
  double kappa = 2.0;         // collapse at κ·x_inst [-], κ ≥ 1
  double v_rest_mps = 1e-7;   // SPEC §3 rest threshold [m/s]
  double v_count_mps = 1e-3;  // SPEC §3 impact-count threshold [m/s]
};

inline StepperSetup<double> make_stepper_setup(const WallParameters& w, ModelKind kind, double r_energy,
                                               const StepperOptions& o) {
  StepperSetup<double> s{};
  s.model = model_constants(w, kind);
  s.g_mps2 = w.g_mps2;
  s.dt_s = o.dt_s;
  s.sqrt_r = std::sqrt(r_energy);
  for (int i = 0; i < 2; ++i) {
    const Side side = i == 0 ? Side::negative : Side::positive;
    s.x_inst_m[i] = x_inst_m(s.model, side, w.g_mps2);
    s.x_collapse_m[i] = o.kappa * s.x_inst_m[i];
  }
  s.v_rest_mps = o.v_rest_mps;
  s.v_count_mps = o.v_count_mps;
  return s;
}

template <typename Other>
StepperSetup<Other> cast_setup(const StepperSetup<double>& s) {
  StepperSetup<Other> o;
  o.model = s.model.template cast<Other>();
  o.g_mps2 = Other(s.g_mps2);
  o.dt_s = Other(s.dt_s);
  o.sqrt_r = Other(s.sqrt_r);
  for (int i = 0; i < 2; ++i) {
    o.x_inst_m[i] = Other(s.x_inst_m[i]);
    o.x_collapse_m[i] = Other(s.x_collapse_m[i]);
  }
  o.v_rest_mps = Other(s.v_rest_mps);
  o.v_count_mps = Other(s.v_count_mps);
  return o;
}

// The floating-point formats and bounds of RockingSegments.
template <typename Scalar>
struct RockingStepperTypes {
  using Length = Scalar;
  using Speed = Scalar;
  using Accel = Scalar;
  using Fraction = Scalar;
  // Never metered (hosts only): no costs (core/work_meter.hpp).
  static constexpr WorkCosts kWork{0, 0, 0, 0};
};

template <typename Scalar>
class RockingStepper : public RockingSegments<RockingStepper<Scalar>, RockingStepperTypes<Scalar>> {
  using Base = RockingSegments<RockingStepper<Scalar>, RockingStepperTypes<Scalar>>;
  friend Base;

 public:
  using typename Base::Report;
  using Base::step;
  // Iterations of the bracketed root finder that locates impacts and collapse inside a step.
  static constexpr int kRootIterations = 64;

  RockingStepper() = default;

  void init(const StepperSetup<Scalar>& setup) {
    setup_ = setup;
    nominal_ = setup;
    reset(Scalar(0), Scalar(0));
  }

  // Wall at rest, vertical, with the given input at the current instant.
  void reset(Scalar ug_mps2, Scalar vg_mps2) {
    this->rest_vertical();
    ug_prev_ = ug_mps2;
    vg_prev_ = vg_mps2;
    step_done_ = true;  // a step stopped inside (metered) is abandoned
  }

  // Places the wall in motion (free-rocking tests, restarts). Side follows x, or ẋ when x = 0.
  void set_state(Scalar x_m, Scalar xd_mps, Scalar ug_mps2, Scalar vg_mps2) {
    reset(ug_mps2, vg_mps2);
    this->place(x_m, xd_mps);
    this->state_.xdd_mps2 = acceleration(this->side_, this->state_.x_m, ug_mps2, vg_mps2);
  }

  // The step in pieces paid from a meter (core/work_meter.hpp): begin_step(), then continue_step() until it returns
  // true; step_report() is then the step's report. step(ug, vg) is both at once (RockingSegments).
  void begin_step(Scalar ug_mps2, Scalar vg_mps2) {
    this->report_ = Report{};
    step_done_ = true;
    if (this->collapsed_) return;
    if (!(setup_.g_mps2 + vg_mps2 > Scalar(0))) {
      this->report_.input_invalid = true;
      ug_prev_ = ug_mps2;
      vg_prev_ = vg_mps2;
      return;
    }
    ug_next_ = ug_mps2;
    vg_next_ = vg_mps2;
    step_done_ = false;
    this->begin_segments();
  }
  template <typename Meter>
  bool continue_step(Meter& meter) {
    if (step_done_) return true;
    if (!this->run_segments(meter)) return false;
    ug_prev_ = ug_next_;
    vg_prev_ = vg_next_;
    step_done_ = true;
    return true;
  }
  // A step begun (begin_step) whose continue_step() has not yet returned true: a metered caller stopped inside it.
  bool step_in_progress() const { return !step_done_; }

  // The velocity ratio at impact √r from now on (the observer's estimate of the real wall's restitution).
  void set_sqrt_r(Scalar sqrt_r) { setup_.sqrt_r = sqrt_r; }

  // The wall's capacity and stiffness from now on (the observer's estimate, SPEC §9): c_s (the gravity and overburden
  // parts of p6) times kc, k (those of p4, and of p5) times kk, so x_inst and κ·x_inst scale by kc/kk. The ground's
  // terms (γ, the ü·x term) stay. (1, 1) is the setup's wall; only the observer calls this (open loop never does).
  void set_capacity_scales(Scalar kc, Scalar kk) {
    ModelConstants<Scalar>& m = setup_.model;
    const ModelConstants<Scalar>& n = nominal_.model;
    for (int i = 0; i < 2; ++i) {
      m.c6_fp[i] = n.c6_fp[i] * kc;
      m.c4_fp[i] = n.c4_fp[i] * kk;
      setup_.x_inst_m[i] = nominal_.x_inst_m[i] * kc / kk;
      setup_.x_collapse_m[i] = nominal_.x_collapse_m[i] * kc / kk;
    }
    m.c6_g = n.c6_g * kc;
    m.c4_g = n.c4_g * kk;
    m.c5_fp = n.c5_fp * kk;
    m.c5_g = n.c5_g * kk;
  }

  const MotionState<Scalar>& state() const { return this->state_; }
  const StepperSetup<Scalar>& setup() const { return setup_; }
  Scalar x_inst_m(Side s) const { return setup_.x_inst_m[side_index(s)]; }

  // Acceleration from the equation of motion on `side` at x with the given input [m/s²].
  Scalar acceleration(Side side, Scalar x_m, Scalar ug_mps2, Scalar vg_mps2) const {
    const Coefficients<Scalar> k = evaluate(setup_.model, side, ug_mps2, setup_.g_mps2 + vg_mps2);
    return force_at(k, x_m) / mass_at(k, x_m);
  }

 private:
  // A segment: the state it starts from, at θ_from, on the current side.
  struct Segment {
    MotionState<Scalar> from;
    Scalar theta_from;
    Side side;
  };
  // An event inside a segment: its fraction of the step.
  struct Located {
    Scalar theta;
  };

  Scalar ug_at(Scalar theta) const { return ug_prev_ + (ug_next_ - ug_prev_) * theta; }
  Scalar vg_at(Scalar theta) const { return vg_prev_ + (vg_next_ - vg_prev_) * theta; }

  Coefficients<Scalar> coefficients_at(Side side, Scalar theta) const {
    return evaluate(setup_.model, side, ug_at(theta), setup_.g_mps2 + vg_at(theta));
  }

  // s·p6(s) at x = 0 along the step: > 0 means the ground drives the wall out towards side s (SPEC §2).
  // Only p6 is needed, so it is formed directly rather than through evaluate(): this runs every step at rest.
  Scalar drive(Side side, Scalar theta) const {
    const ModelConstants<Scalar>& c = setup_.model;
    const Scalar restoring = c.c6_fp[side_index(side)] + c.c6_g * (setup_.g_mps2 + vg_at(theta));
    const Scalar push = c.c6_u * ug_at(theta);
    return side == Side::positive ? -restoring - push : -restoring + push;
  }
  Scalar drive_at_end(Side side) const { return drive(side, Scalar(1)); }

  // s·p6 is affine in θ (input linear in time), so the crossing is exact.
  Scalar start_crossing(Scalar theta, Scalar now, Scalar end) const {
    return theta + (Scalar(1) - theta) * (-now) / (end - now);
  }

  Scalar accel_at_hinge(Side side, Scalar theta) const {
    const Coefficients<Scalar> k = coefficients_at(side, theta);
    return force_at(k, Scalar(0)) / mass_at(k, Scalar(0));
  }

  Scalar rebound(Scalar v_mps) const { return setup_.sqrt_r * v_mps; }

  Segment begin_segment(Scalar theta) const { return Segment{this->state_, theta, this->side_}; }

  // Newmark from the segment's start over a sub-step that ends at `theta_end`, on its side.
  MotionState<Scalar> trial(const Segment& g, Scalar theta_end) const {
    const Scalar h = (theta_end - g.theta_from) * setup_.dt_s;
    return newmark_step(coefficients_at(g.side, theta_end), setup_.model.kind, g.from, h);
  }
  MotionState<Scalar> end_of(const Segment& g) const { return trial(g, Scalar(1)); }
  MotionState<Scalar> state_at(const Segment& g, Located at) const { return trial(g, at.theta); }

  // θ in (θ_from, 1] where s·x(θ) reaches `level`, by Illinois regula falsi on the Newmark step from the segment's
  // start, bracketed by the segment's ends. When the segment starts on the hinge (right after an impact) and the
  // level is the hinge, the function is divided by the sub-step so the root at the start point does not shadow the
  // one we want.
  Located locate(const Segment& g, const MotionState<Scalar>& end, Scalar level, Report& report) const {
    ++report.events_located;
    const Scalar x0 = Base::signed_x(g.side, g.from.x_m);
    const Scalar x1 = Base::signed_x(g.side, end.x_m);
    const bool divide_by_h = level == Scalar(0) && g.from.x_m == Scalar(0);
    Scalar lo = g.theta_from, hi = Scalar(1);
    Scalar g_lo = x0 - level, g_hi = x1 - level;
    if (divide_by_h) {
      g_lo = Base::signed_v(g.side, g.from.xd_mps) * setup_.dt_s;  // limit of s·x(θ)/(θ − θ_from) at θ_from, times dt
      g_hi = x1 / (Scalar(1) - g.theta_from);
    }
    int side_kept = 0;
    for (int it = 0; it < kRootIterations; ++it) {
      if (g_hi == g_lo) break;
      Scalar mid = hi - g_hi * (hi - lo) / (g_hi - g_lo);
      if (!(mid > lo && mid < hi)) mid = (lo + hi) / Scalar(2);
      if (mid == lo || mid == hi) break;
      ++report.locate_iterations;
      const MotionState<Scalar> s = trial(g, mid);
      Scalar value = Base::signed_x(g.side, s.x_m) - level;
      if (divide_by_h) value = value / (mid - g.theta_from);
      if (value == Scalar(0)) return Located{mid};
      if ((value > Scalar(0)) == (g_hi > Scalar(0))) {
        hi = mid;
        g_hi = value;
        if (side_kept == 1) g_lo = g_lo / Scalar(2);
        side_kept = 1;
      } else {
        lo = mid;
        g_lo = value;
        if (side_kept == -1) g_hi = g_hi / Scalar(2);
        side_kept = -1;
      }
    }
    return Located{hi};
  }

  StepperSetup<Scalar> setup_{};
  StepperSetup<Scalar> nominal_{};  // the setup as given (set_capacity_scales scales from it)
  Scalar ug_prev_{}, vg_prev_{};
  Scalar ug_next_{}, vg_next_{};
  bool step_done_ = true;  // the step's segments are done (or there were none to do)
};

}  // namespace rockwatch::core
