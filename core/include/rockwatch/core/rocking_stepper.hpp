// The two-block rocking integrator (SPEC §2–4): constant step, Newmark with impacts located inside the step,
// start of motion at the threshold, rest logic and collapse located inside the step.
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

// What happened inside one step. Fractions are of the step length, in [0, 1].
template <typename Scalar>
struct StepReport {
  bool input_invalid = false;     // G = g + v̈ ≤ 0 at the step end: outside the model, state held
  bool started = false;           // rocking started from rest in this step
  Scalar start_fraction{};
  std::uint16_t impacts_counted = 0;  // impacts with |ẋ⁻| ≥ v_count
  std::uint16_t impacts_total = 0;    // all impacts
  Scalar first_impact_fraction{};     // the first impact of the step: when,
  Scalar first_impact_v_before_mps{}; //   ẋ⁻ [m/s]
  Scalar first_impact_v_after_mps{};  //   and ẋ⁺ = √r·ẋ⁻ [m/s], also when the impact puts the wall at rest
                                      //   (FixedStepReport writes 0 there)
  bool came_to_rest = false;
  bool exceeded = false;          // |x| rose through x_inst in this step (first time in the step)
  Scalar exceed_fraction{};
  bool collapsed = false;         // |x| reached κ·x_inst; the stepper stops
  Scalar collapse_fraction{};
  bool segment_cap_reached = false;  // Zeno guard: too many impacts in one step; wall put at rest
};

template <typename Scalar>
class RockingStepper {
 public:
  // Upper bound on impacts handled inside one step. Reached only when impacts are microseconds apart, i.e. at
  // velocities of ~1e-5 m/s, where the wall is at rest for every practical purpose.
  static constexpr int kMaxSegmentsPerStep = 64;
  // Iterations of the bracketed root finder that locates impacts and collapse inside a step.
  static constexpr int kRootIterations = 64;

  RockingStepper() = default;

  void init(const StepperSetup<Scalar>& setup) {
    setup_ = setup;
    reset(Scalar(0), Scalar(0));
  }

  // Wall at rest, vertical, with the given input at the current instant.
  void reset(Scalar ug_mps2, Scalar vg_mps2) {
    state_ = MotionState<Scalar>{Scalar(0), Scalar(0), Scalar(0)};
    side_ = Side::positive;
    moving_ = false;
    collapsed_ = false;
    ug_prev_ = ug_mps2;
    vg_prev_ = vg_mps2;
  }

  // Places the wall in motion (free-rocking tests, restarts). Side follows x, or ẋ when x = 0.
  void set_state(Scalar x_m, Scalar xd_mps, Scalar ug_mps2, Scalar vg_mps2) {
    reset(ug_mps2, vg_mps2);
    state_.x_m = x_m;
    state_.xd_mps = xd_mps;
    if (x_m != Scalar(0)) {
      side_ = x_m > Scalar(0) ? Side::positive : Side::negative;
    } else {
      side_ = xd_mps < Scalar(0) ? Side::negative : Side::positive;
    }
    moving_ = x_m != Scalar(0) || xd_mps != Scalar(0);
    state_.xdd_mps2 = acceleration(side_, state_.x_m, ug_mps2, vg_mps2);
  }

  // Advances one step of setup.dt_s to the given input at the step end.
  StepReport<Scalar> step(Scalar ug_mps2, Scalar vg_mps2) {
    StepReport<Scalar> report;
    if (collapsed_) return report;
    if (!(setup_.g_mps2 + vg_mps2 > Scalar(0))) {
      report.input_invalid = true;
      ug_prev_ = ug_mps2;
      vg_prev_ = vg_mps2;
      return report;
    }
    ug_next_ = ug_mps2;
    vg_next_ = vg_mps2;
    Scalar theta = Scalar(0);  // position inside the step, fraction of dt
    for (int segment = 0; segment < kMaxSegmentsPerStep; ++segment) {
      if (!moving_) {
        if (!try_start(theta, report)) break;
      }
      if (advance_segment(theta, report)) break;  // reached the step end, or collapsed
      if (segment + 1 == kMaxSegmentsPerStep) {
        report.segment_cap_reached = true;
        put_at_rest(report);
      }
    }
    ug_prev_ = ug_mps2;
    vg_prev_ = vg_mps2;
    return report;
  }

  // The velocity ratio at impact √r from now on (the observer's estimate of the real wall's restitution).
  void set_sqrt_r(Scalar sqrt_r) { setup_.sqrt_r = sqrt_r; }

  const MotionState<Scalar>& state() const { return state_; }
  Side side() const { return side_; }
  bool moving() const { return moving_; }
  bool collapsed() const { return collapsed_; }
  const StepperSetup<Scalar>& setup() const { return setup_; }
  Scalar x_inst_m(Side s) const { return setup_.x_inst_m[side_index(s)]; }

  // Acceleration from the equation of motion on `side` at x with the given input [m/s²].
  Scalar acceleration(Side side, Scalar x_m, Scalar ug_mps2, Scalar vg_mps2) const {
    const Coefficients<Scalar> k = evaluate(setup_.model, side, ug_mps2, setup_.g_mps2 + vg_mps2);
    return force_at(k, x_m) / mass_at(k, x_m);
  }

 private:
  Scalar ug_at(Scalar theta) const { return ug_prev_ + (ug_next_ - ug_prev_) * theta; }
  Scalar vg_at(Scalar theta) const { return vg_prev_ + (vg_next_ - vg_prev_) * theta; }

  Coefficients<Scalar> coefficients_at(Side side, Scalar theta) const {
    return evaluate(setup_.model, side, ug_at(theta), setup_.g_mps2 + vg_at(theta));
  }

  // s·p6(s) at x = 0 along the step: > 0 means the ground drives the wall out towards side s (SPEC §2).
  // Only p6 is needed, so it is formed directly rather than through evaluate(): this runs every step at rest.
  Scalar driving_force(Side side, Scalar theta) const {
    const ModelConstants<Scalar>& c = setup_.model;
    const Scalar restoring = c.c6_fp[side_index(side)] + c.c6_g * (setup_.g_mps2 + vg_at(theta));
    const Scalar push = c.c6_u * ug_at(theta);
    return side == Side::positive ? -restoring - push : -restoring + push;
  }

  // At rest from `theta`: if the input crosses a threshold before the step end, start rocking at the
  // crossing (input linear in time, so s·p6 is affine in θ and the crossing is exact). Returns true if moving.
  bool try_start(Scalar& theta, StepReport<Scalar>& report) {
    for (int candidate = 0; candidate < 2; ++candidate) {
      const Side side = candidate == 0 ? Side::positive : Side::negative;
      const Scalar f_end = driving_force(side, Scalar(1));
      if (!(f_end > Scalar(0))) continue;
      const Scalar f_now = driving_force(side, theta);
      Scalar start = theta;
      if (f_now < Scalar(0)) start = theta + (Scalar(1) - theta) * (-f_now) / (f_end - f_now);
      theta = start;
      side_ = side;
      moving_ = true;
      state_ = MotionState<Scalar>{Scalar(0), Scalar(0), Scalar(0)};
      const Coefficients<Scalar> k = coefficients_at(side, theta);
      state_.xdd_mps2 = force_at(k, Scalar(0)) / mass_at(k, Scalar(0));
      if (!report.started) {
        report.started = true;
        report.start_fraction = theta;
      }
      return true;
    }
    return false;
  }

  // Newmark from `from` over a sub-step that ends at `theta_end`, on the current side.
  MotionState<Scalar> trial(const MotionState<Scalar>& from, Scalar theta_from, Scalar theta_end) const {
    const Scalar h = (theta_end - theta_from) * setup_.dt_s;
    return newmark_step(coefficients_at(side_, theta_end), setup_.model.kind, from, h);
  }

  Scalar signed_x(Scalar x_m) const { return side_ == Side::positive ? x_m : -x_m; }

  // Locates θ in (lo, hi] where s·x(θ) − level changes sign, by Illinois regula falsi on the Newmark step from
  // `from` at `theta_from`. `g_lo`/`g_hi` are the function values at the bracket ends. When the segment
  // starts at x = 0 (right after an impact), the function is divided by the sub-step so the root at the
  // start point does not shadow the one we want.
  Scalar locate(const MotionState<Scalar>& from, Scalar theta_from, Scalar level, bool divide_by_h,
                Scalar lo, Scalar g_lo, Scalar hi, Scalar g_hi) const {
    int side_kept = 0;
    for (int it = 0; it < kRootIterations; ++it) {
      if (g_hi == g_lo) break;
      Scalar mid = hi - g_hi * (hi - lo) / (g_hi - g_lo);
      if (!(mid > lo && mid < hi)) mid = (lo + hi) / Scalar(2);
      if (mid == lo || mid == hi) break;
      const MotionState<Scalar> s = trial(from, theta_from, mid);
      Scalar g = signed_x(s.x_m) - level;
      if (divide_by_h) g = g / (mid - theta_from);
      if (g == Scalar(0)) return mid;
      if ((g > Scalar(0)) == (g_hi > Scalar(0))) {
        hi = mid;
        g_hi = g;
        if (side_kept == 1) g_lo = g_lo / Scalar(2);
        side_kept = 1;
      } else {
        lo = mid;
        g_lo = g;
        if (side_kept == -1) g_hi = g_hi / Scalar(2);
        side_kept = -1;
      }
    }
    return hi;
  }

  // Integrates from θ to the step end on the current side, stopping at the first impact or at collapse.
  // Returns true when the step is finished (end reached or collapsed), false after an impact.
  bool advance_segment(Scalar& theta, StepReport<Scalar>& report) {
    const MotionState<Scalar> from = state_;
    const Scalar theta_from = theta;
    const Scalar x0 = signed_x(from.x_m);
    const bool at_hinge = from.x_m == Scalar(0);
    if (at_hinge && signed_x(from.xd_mps) < Scalar(0)) {
      impact(from, theta, report);  // sitting on the hinge and moving across it
      return false;
    }
    if (!(theta < Scalar(1))) return true;
    const MotionState<Scalar> end = trial(from, theta, Scalar(1));
    const Scalar x1 = signed_x(end.x_m);
    if (x1 < Scalar(0)) {
      // Crossed x = 0 inside the step: locate the crossing and apply the impact there (SPEC §3, §4.1).
      Scalar g_lo = x0, g_hi = x1;
      if (at_hinge) {
        g_lo = signed_x(from.xd_mps) * setup_.dt_s;  // limit of s·x(θ)/(θ − θ_from) at θ_from, times dt
        g_hi = x1 / (Scalar(1) - theta_from);
      }
      const Scalar root = locate(from, theta_from, Scalar(0), at_hinge, theta_from, g_lo, Scalar(1), g_hi);
      MotionState<Scalar> at = trial(from, theta_from, root);
      at.x_m = Scalar(0);
      theta = root;
      impact(at, theta, report);
      return false;
    }
    const Side side = side_;
    const Scalar inst = setup_.x_inst_m[side_index(side)];
    const Scalar limit = setup_.x_collapse_m[side_index(side)];
    if (x0 < inst && x1 >= inst && !report.exceeded) {
      report.exceeded = true;
      report.exceed_fraction = locate(from, theta_from, inst, false, theta_from, x0 - inst, Scalar(1), x1 - inst);
    }
    if (x1 >= limit) {
      const Scalar root = locate(from, theta_from, limit, false, theta_from, x0 - limit, Scalar(1), x1 - limit);
      state_ = trial(from, theta_from, root);
      state_.x_m = side == Side::positive ? limit : -limit;
      report.collapsed = true;
      report.collapse_fraction = root;
      collapsed_ = true;
      moving_ = false;
      return true;
    }
    state_ = end;
    theta = Scalar(1);
    return true;
  }

  // Impact at x = 0 with velocity `at.xd_mps`: ẋ⁺ = √r ẋ⁻ into the other side, ẍ⁺ from its equation of motion,
  // or rest when the wall barely moves and the ground does not drive it out (SPEC §3).
  void impact(const MotionState<Scalar>& at, Scalar theta, StepReport<Scalar>& report) {
    const Scalar v_before = at.xd_mps;
    const Scalar speed = v_before < Scalar(0) ? -v_before : v_before;
    const Scalar v_after = setup_.sqrt_r * v_before;
    const Scalar speed_after = setup_.sqrt_r * speed;
    if (report.impacts_total == 0) {
      report.first_impact_fraction = theta;
      report.first_impact_v_before_mps = v_before;
      report.first_impact_v_after_mps = v_after;
    }
    if (report.impacts_total < UINT16_MAX) ++report.impacts_total;
    if (speed >= setup_.v_count_mps && report.impacts_counted < UINT16_MAX) ++report.impacts_counted;
    side_ = opposite(side_);
    if (speed_after < setup_.v_rest_mps && !(driving_force(side_, theta) > Scalar(0))) {
      put_at_rest(report);
      return;
    }
    const Coefficients<Scalar> k = coefficients_at(side_, theta);
    state_.x_m = Scalar(0);
    state_.xd_mps = v_after;
    state_.xdd_mps2 = force_at(k, Scalar(0)) / mass_at(k, Scalar(0));
  }

  void put_at_rest(StepReport<Scalar>& report) {
    state_ = MotionState<Scalar>{Scalar(0), Scalar(0), Scalar(0)};
    moving_ = false;
    report.came_to_rest = true;
  }

  StepperSetup<Scalar> setup_{};
  MotionState<Scalar> state_{};
  Side side_ = Side::positive;
  bool moving_ = false;
  bool collapsed_ = false;
  Scalar ug_prev_{}, vg_prev_{};
  Scalar ug_next_{}, vg_next_{};
};

}  // namespace rockwatch::core
