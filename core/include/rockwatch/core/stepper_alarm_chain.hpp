// The one composition of the per-step chain: rocking stepper → instability indicators → alarm state machine,
// for either stepper (core::RockingStepper<double>, core::FixedRockingStepper). Used by the firmware's engine
// (firmware::WallEngine), the host's double engine (sim::DoubleWallEngine) and both paths of sim::analyse, so the
// order of the stages and what the alarm sees are written once.
//
// The stepper-specific parts (report, constants and indicator types, how the stepper and the constants are set up)
// come from AlarmChainTraits, specialised below for the two steppers. The output is written into a caller-owned
// AlarmChainOutput (the firmware engine extends it with its inputs): no copy per sample.
//
// Core rules: header-only, no heap, no exceptions, no I/O; init() is initialisation-time code (double), the rest
// has the stepper's bounds on work.
#pragma once

#include <cstdint>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/fixed_instability_indicators.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/instability_indicators.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

namespace rockwatch::core {

template <typename Stepper>
struct AlarmChainTraits;

template <>
struct AlarmChainTraits<RockingStepper<double>> {
  using Input = double;
  using Report = StepReport<double>;
  using Constants = InstabilityConstants<double>;
  using Indicators = InstabilityIndicators<double>;
  static FixedSetupError init_stepper(RockingStepper<double>& s, const StepperSetup<double>& setup) {
    s.init(setup);
    return FixedSetupError::ok;
  }
  static bool make_constants(const StepperSetup<double>& setup, const AlarmSettings& a, Constants& out) {
    out = make_instability_constants(setup, a);
    return true;
  }
};

template <>
struct AlarmChainTraits<FixedRockingStepper> {
  using Input = AccelQ7_56;
  using Report = FixedStepReport;
  using Constants = FixedInstabilityConstants;
  using Indicators = FixedInstabilityIndicators;
  static FixedSetupError init_stepper(FixedRockingStepper& s, const StepperSetup<double>& setup) {
    return s.init(setup);
  }
  static bool make_constants(const StepperSetup<double>& setup, const AlarmSettings& a, Constants& out) {
    return make_fixed_instability_constants(setup, a, out);
  }
};

template <typename Stepper>
struct AlarmChainOutput {
  typename AlarmChainTraits<Stepper>::Report step{};              // what the stepper did inside the step
  typename AlarmChainTraits<Stepper>::Indicators indicators{};    // conditions, predicted time, energy ratio
  AlarmUpdate alarm{};                                            // level after the step, reasons, transition flag
};

// Why init() refused. Values are stable: append, never renumber.
enum class AlarmChainError : std::uint8_t {
  ok = 0,
  stepper_setup = 1,        // the fixed-point stepper refused the setup (setup_error() says why)
  indicator_constants = 2,  // x_inst or ω outside the fixed-point indicator formats
};

template <typename Stepper>
class StepperAlarmChain {
 public:
  using Traits = AlarmChainTraits<Stepper>;
  using Input = typename Traits::Input;
  using Report = typename Traits::Report;
  using Output = AlarmChainOutput<Stepper>;

  // Initialisation time. The alarm holds a level for hold_samples(alarm, dt_s) steps.
  AlarmChainError init(const StepperSetup<double>& setup, const AlarmSettings& alarm, double dt_s) {
    setup_error_ = Traits::init_stepper(stepper_, setup);
    if (setup_error_ != FixedSetupError::ok) return AlarmChainError::stepper_setup;
    if (!Traits::make_constants(setup, alarm, constants_)) return AlarmChainError::indicator_constants;
    alarm_.init(hold_samples(alarm, dt_s));
    return AlarmChainError::ok;
  }

  // Wall at rest with this input as the current one, alarm QUIET.
  void reset(Input ug_mps2, Input vg_mps2) {
    stepper_.reset(ug_mps2, vg_mps2);
    alarm_.reset();
  }

  // One step of the stepper only (callers that do not need the indicators this step).
  void step_motion(Input ug_mps2, Input vg_mps2, Output& out) { out.step = stepper_.step(ug_mps2, vg_mps2); }

  // The indicators of the stepper's state and out.step, then the alarm.
  void evaluate(Output& out) {
    out.indicators = evaluate_instability(constants_, stepper_, out.step);
    out.alarm = alarm_.update(out.indicators.conditions);
  }

  // One step: stepper → indicators → alarm.
  void step(Input ug_mps2, Input vg_mps2, Output& out) {
    step_motion(ug_mps2, vg_mps2, out);
    evaluate(out);
  }

  // One step with a state observer between the stepper and the indicators (core/wall_observer.hpp): the observer
  // corrects the stepper's state with the sensor samples up to the step end, so the indicators and the alarm see the
  // fused state. t_us: the step end on the sensor clock; step_us: the step length [µs].
  template <typename Observer>
  typename Observer::StepOutcome step_observed(Input ug_mps2, Input vg_mps2, Observer& observer, std::int64_t t_us,
                                               std::int64_t step_us, Output& out) {
    step_motion(ug_mps2, vg_mps2, out);
    const auto outcome = observer.after_step(stepper_, out.step, ug_mps2, vg_mps2, t_us, step_us);
    evaluate(out);
    return outcome;
  }

  // The state restarts from rest (state unknown after a long gap or a publisher restart) with this input as the
  // current one; the alarm keeps its level (a latched COLLAPSED stays, others fall only through the hold time).
  void restart_motion(Input ug_mps2, Input vg_mps2, Output& out) {
    stepper_.reset(ug_mps2, vg_mps2);
    out.step = Report{};
    evaluate(out);
  }

  const Stepper& stepper() const { return stepper_; }
  FixedSetupError setup_error() const { return setup_error_; }

 private:
  Stepper stepper_{};
  typename Traits::Constants constants_{};
  InstabilityAlarm alarm_{};
  FixedSetupError setup_error_ = FixedSetupError::ok;
};

}  // namespace rockwatch::core
