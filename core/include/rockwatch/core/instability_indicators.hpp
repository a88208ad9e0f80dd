// The physical conditions the instability alarm (alarm.hpp) acts on, evaluated from the rocking stepper's state at
// the end of a step, in the stepper's own arithmetic (double or float here). This header is the one home of the
// definitions below and of the prediction cap; fixed_instability_indicators.hpp evaluates the same definitions in
// fixed point (it says why it is a second implementation and not this template instantiated on a fixed type).
//
// Definitions. On the current side s (index i = side_index(s)), with x_i = x_inst,s the static instability
// displacement of that side (StepperSetup::x_inst_m):
//   y  = s·x − x_i              distance past the instability point (< 0 inside it; s·x = |x|)
//   ẏ  = s·ẋ                    outward velocity (> 0 moving away from the vertical)
//   ω² = −p4(s)/p1              p4, p1 of the LINEAR model in free motion (ü = v̈ = 0, G = g): p4 < 0, so ω² > 0 and
//                               the rocking wall is unstable about x_inst: ÿ = ω² y in free motion (linear model)
//   ρ  = E/E_barrier = 1 + (ẏ² − ω² y²)/(ω² x_i²)
// ρ is exact for the linear model (SPEC §2: E = ½ p1 ẋ² + c|x| − ½ k x², E_barrier = c²/2k, x_i = c/k, k = |p4|,
// so E − E_barrier = ½ p1 ẏ² − ½ k y²). For the full model it is the linear approximation about x_i (whose x_i is
// the full model's own root), good to the size of the nonlinear terms (< 2 %, SPEC §1).
//
// Conditions (AlarmConditions):
//   moving                         stepper.moving()
//   over_warning_displacement      |x| ≥ λ_w·x_i
//   over_instability_displacement  |x| ≥ x_i
//   over_collapse_displacement     stepper.collapsed() (|x| reached κ·x_inst)
//   energy_over_barrier_outward    moving and ẏ > 0 and (ρ ≥ energy_margin and |x| ≥ energy_min_x·x_i, or ρ ≥ 1 and
//                                  0 < t_to_instability ≤ imminent_horizon_s: about to pass x_inst in free motion;
//                                  horizon 0 = off; energy_min_x 0 = the margin everywhere)
//   input_invalid                  the step's report says G = g + v̈ ≤ 0 (state held)
//   arithmetic_saturated           always false in floating point
//
// Predicted time to reach |x| = x_i under zero further input (closed form of the linear model:
// y(t) = y0 cosh ωt + (ẏ0/ω) sinh ωt, which reaches 0 when tanh ωt = −ω y0/ẏ0):
//   |x| ≥ x_i                     → 0 (valid)
//   ẏ > 0 and ρ ≥ 1               → z = −ω y/ẏ ∈ (0, 1], t = atanh(z)/ω, capped at t_max (z = 1 → t_max) (valid)
//   otherwise                     → no prediction (t_valid = false: the wall turns back, or is at rest)
//
// Core rules: no heap, no exceptions, no I/O; constant work per call (no loops over time).
#pragma once

#include <cmath>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

namespace rockwatch::core {

// Longest predicted time to instability reported [s]: beyond it the prediction says "not soon" and nothing more
// (z → 1 means the wall creeps up to x_inst with just the barrier energy; the time grows without bound).
inline constexpr double kInstabilityPredictionCap_s = 60.0;

// Everything evaluate_instability needs, prepared once in double (make_instability_constants) and cast to Scalar.
// Per side arrays are indexed by side_index (0 = side −1, 1 = side +1).
template <typename Scalar>
struct InstabilityConstants {
  Scalar x_inst_m[2];               // x_i [m]
  Scalar x_warning_m[2];            // λ_w·x_i [m]
  Scalar x_energy_min_m[2];         // energy_min_x·x_i: the energy margin's rule applies from here [m]
  Scalar omega_rps[2];              // ω [rad/s]
  Scalar omega2_rps2[2];            // ω² [1/s²]
  Scalar inv_omega2_x_inst2_s2pm2[2];  // 1/(ω² x_i²) [s²/m²]: ρ without a division per step
  Scalar energy_margin;             // IMMINENT by energy when ρ ≥ this [-], ≥ 1
  Scalar horizon_s;                 // ... or when ρ ≥ 1 and the predicted time to x_inst ≤ this [s] (0 = off)
  Scalar t_max_s;                   // cap of the predicted time [s]
};

// Initialisation-time code. ω uses the linear model's p1 and p4 whatever setup.model.kind is (p1 and p4 do not
// depend on the model kind); x_i is the setup's (the full model's root for the full model).
inline InstabilityConstants<double> make_instability_constants(const StepperSetup<double>& setup,
                                                               const AlarmSettings& settings) {
  InstabilityConstants<double> c{};
  for (int i = 0; i < 2; ++i) {
    const Side side = i == 0 ? Side::negative : Side::positive;
    const Coefficients<double> free_k = evaluate(setup.model, side, 0.0, setup.g_mps2);
    const double omega2 = -free_k.p4 / free_k.p1;
    const double x_inst = setup.x_inst_m[i];
    c.x_inst_m[i] = x_inst;
    c.x_warning_m[i] = settings.lambda_warning * x_inst;
    c.x_energy_min_m[i] = settings.energy_min_x * x_inst;
    c.omega2_rps2[i] = omega2;
    c.omega_rps[i] = std::sqrt(omega2);
    c.inv_omega2_x_inst2_s2pm2[i] = 1.0 / (omega2 * x_inst * x_inst);
  }
  c.energy_margin = settings.energy_margin;
  c.horizon_s = settings.imminent_horizon_s;
  c.t_max_s = kInstabilityPredictionCap_s;
  return c;
}

template <typename Other>
InstabilityConstants<Other> cast_instability_constants(const InstabilityConstants<double>& c) {
  InstabilityConstants<Other> o;
  for (int i = 0; i < 2; ++i) {
    o.x_inst_m[i] = Other(c.x_inst_m[i]);
    o.x_warning_m[i] = Other(c.x_warning_m[i]);
    o.x_energy_min_m[i] = Other(c.x_energy_min_m[i]);
    o.omega_rps[i] = Other(c.omega_rps[i]);
    o.omega2_rps2[i] = Other(c.omega2_rps2[i]);
    o.inv_omega2_x_inst2_s2pm2[i] = Other(c.inv_omega2_x_inst2_s2pm2[i]);
  }
  o.energy_margin = Other(c.energy_margin);
  o.horizon_s = Other(c.horizon_s);
  o.t_max_s = Other(c.t_max_s);
  return o;
}

template <typename Scalar>
struct InstabilityIndicators {
  AlarmConditions conditions;
  bool t_valid = false;             // a prediction exists (see the header comment)
  Scalar t_to_instability_s{};      // predicted time to |x| = x_inst under zero further input [s], when t_valid
  Scalar energy_ratio{};            // ρ = E/E_barrier of the current side (linear model) [-]
};

// The indicators after a step (or after set_state, with a default StepReport).
template <typename Scalar>
InstabilityIndicators<Scalar> evaluate_instability(const InstabilityConstants<Scalar>& c,
                                                   const RockingStepper<Scalar>& stepper,
                                                   const StepReport<Scalar>& report) {
  const int i = side_index(stepper.side());
  const bool positive = stepper.side() == Side::positive;
  const MotionState<Scalar>& st = stepper.state();
  const Scalar abs_x = st.x_m < Scalar(0) ? -st.x_m : st.x_m;
  const Scalar x_i = c.x_inst_m[i];
  const Scalar y = abs_x - x_i;  // s·x = |x| on the current side (x = 0 on the side being entered: 0 too)
  const Scalar yd = positive ? st.xd_mps : -st.xd_mps;
  const Scalar omega2_y2 = c.omega2_rps2[i] * y * y;

  InstabilityIndicators<Scalar> out;
  out.energy_ratio = Scalar(1) + (yd * yd - omega2_y2) * c.inv_omega2_x_inst2_s2pm2[i];

  AlarmConditions& k = out.conditions;
  k.moving = stepper.moving();
  k.over_warning_displacement = abs_x >= c.x_warning_m[i];
  k.over_instability_displacement = abs_x >= x_i;
  k.over_collapse_displacement = stepper.collapsed();
  k.energy_over_barrier_outward =
      k.moving && yd > Scalar(0) && out.energy_ratio >= c.energy_margin && abs_x >= c.x_energy_min_m[i];
  k.input_invalid = report.input_invalid;
  k.arithmetic_saturated = false;

  if (k.over_instability_displacement) {
    out.t_valid = true;
    out.t_to_instability_s = Scalar(0);
  } else if (yd > Scalar(0) && out.energy_ratio >= Scalar(1)) {
    out.t_valid = true;
    const Scalar z = -c.omega_rps[i] * y / yd;  // in (0, 1]: y < 0 < ẏ and ẏ ≥ ω|y| (rounding may give 1 + ε)
    if (!(z < Scalar(1))) {
      out.t_to_instability_s = c.t_max_s;
    } else {
      using std::atanh;
      const Scalar t = atanh(z) / c.omega_rps[i];
      out.t_to_instability_s = t < c.t_max_s ? t : c.t_max_s;
    }
    if (k.moving && c.horizon_s > Scalar(0) && out.t_to_instability_s <= c.horizon_s) {
      k.energy_over_barrier_outward = true;  // about to pass x_inst in free motion
    }
  }
  return out;
}

}  // namespace rockwatch::core
