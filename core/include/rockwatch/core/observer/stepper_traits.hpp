// How the wall observer (core/wall_observer.hpp) reads and corrects each stepper, and in which arithmetic it keeps
// its state (Scalar) and its covariance (Cov).
#pragma once

#include "rockwatch/core/fixed_point64.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/observer/observer_types.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

namespace rockwatch::core {

// How the observer reads and corrects a stepper. Specialised for the two steppers.
template <typename Stepper>
struct ObserverStepperTraits;

template <>
struct ObserverStepperTraits<RockingStepper<double>> {
  using Scalar = double;
  using Cov = double;  // the covariance, gains and linearisations
  using Input = double;
  using Report = StepReport<double>;
  static constexpr ObserverWorkCosts kWork{0, 0, 0, 0, 0};  // hosts only: never metered
  static double x(const RockingStepper<double>& s) { return s.state().x_m; }
  static double xd(const RockingStepper<double>& s) { return s.state().xd_mps; }
  static double xdd(const RockingStepper<double>& s) { return s.state().xdd_mps2; }
  static double input(Input v) { return v; }
  static double v_before(const Report& r) { return r.first_impact_v_before_mps; }
  static void set_motion(RockingStepper<double>& s, double x, double xd, Input ug, Input vg) {
    s.set_state(x, xd, ug, vg);
  }
  static void set_sqrt_r(RockingStepper<double>& s, double e) { s.set_sqrt_r(e); }
  static void set_capacity(RockingStepper<double>& s, double kc, double kk, Input, Input) {
    s.set_capacity_scales(kc, kk);
  }
};

template <>
struct ObserverStepperTraits<FixedRockingStepper> {
  using Scalar = ObserverQ10_53;
  // The covariance, the gains and the linearisations in single precision on the M4F's FPU (as PX4's EKF2 on
  // Cortex-M4F/M7): a product is one VMUL.F32 instead of a 128-bit product of Fixed64 (~55 instructions), a division
  // one VDIV.F32. Host and target agree bit for bit: IEEE single, round to nearest, no contraction into fused
  // multiply-adds (-ffp-contract=off in both builds). The state (x, ẋ, e, b, κc, κk) stays in fixed point.
  using Cov = float;
  using Input = AccelQ7_56;
  using Report = FixedStepReport;
  // Upper bounds measured on the emulated M4 (docs/BENCHMARKS.md, "The metered observer"); `superseded` (one ring
  // index moved and one time compared) is a generous bound, not measured: the records never supersede a sample.
  static constexpr ObserverWorkCosts kWork{1000, 5000, 2500, 300, 50};
  static Scalar x(const FixedRockingStepper& s) { return wide_convert<Scalar>(s.x_m()); }
  static Scalar xd(const FixedRockingStepper& s) { return wide_convert<Scalar>(s.xd_mps()); }
  static Scalar xdd(const FixedRockingStepper& s) { return wide_convert<Scalar>(s.xdd_mps2()); }
  static Scalar input(Input v) { return wide_convert<Scalar>(v); }
  static Scalar v_before(const Report& r) { return wide_convert<Scalar>(r.first_impact_v_before_mps); }
  // The observer corrects the state after the step (or set_capacity) whose input is (ug, vg): f and k are the
  // stepper's already (correct_state: no recomputation, the same state as set_state at that input).
  static void set_motion(FixedRockingStepper& s, Scalar x, Scalar xd, Input, Input) {
    s.correct_state(wide_convert<LengthQ1_62>(x), wide_convert<SpeedQ3_60>(xd));
  }
  static void set_sqrt_r(FixedRockingStepper& s, Scalar e) { s.set_sqrt_r(wide_convert<FractionQ1_62>(e)); }
  static void set_capacity(FixedRockingStepper& s, Scalar kc, Scalar kk, Input ug, Input vg) {
    s.set_capacity_scales(wide_convert<GainQ4_59>(kc), wide_convert<GainQ4_59>(kk), ug, vg);
  }
};

}  // namespace rockwatch::core
