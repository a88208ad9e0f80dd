// The monitor's per-sample processing unit: a 3-axis accelerometer sample in, the wall's state and alarm out.
// Sensor axes (Eigen fixed size) → core::StepperAlarmChain over the fixed-point rocking stepper (stepper →
// instability indicators → alarm state machine). init() does all floating-point work and validation; process() then
// runs integer arithmetic only, allocates nothing and takes the same work every sample (bounded loops with fixed
// iteration counts). With the observer enabled (WallEngineConfig::observer_enabled), core::WallObserver over the same
// fixed-point stepper (state ObserverQ10_53, covariance single precision) corrects the state between the stepper and the indicators: its work is
// metered with the stepper's (its pieces paid from the same budget and carried over with the samples). It is the firmware's SampleEngine: the monitor loop runs it behind that seam; the embedded
// build (scripts/embedded-build.sh) compiles it for a Cortex-M4.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/fixed_instability_indicators.hpp"
#include "rockwatch/core/fixed_point_eigen.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/sensor_axes.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/firmware/sample_engine.hpp"

namespace rockwatch::firmware {

using SensorSampleQ = Eigen::Matrix<core::AccelQ7_24, 3, 1>;  // sensor-frame acceleration [m/s²]

// step, indicators, alarm (core::AlarmChainOutput) and the wall-frame inputs used.
struct WallEngineOutput : core::AlarmChainOutput<core::FixedRockingStepper> {
  core::AccelQ7_24 ug_mps2{};                    // the wall-frame inputs used [m/s²]
  core::AccelQ7_24 vg_mps2{};
};

class WallEngine final : public SampleEngine {
 public:
  MonitorArithmetic arithmetic() const override { return MonitorArithmetic::fixed_point; }
  WallEngineError init(const WallEngineConfig& config) override;
  // Wall at rest, alarm QUIET, with the given sample as the current input.
  void reset(const SensorSampleQ& sensor_mps2);
  // One sample. Bounded work; no allocation.
  const WallEngineOutput& process(const SensorSampleQ& sensor_mps2);
  // One sample already in the wall's frame at the engine's precision (the monitor's LCM input carries ü and v̈ as
  // doubles: converting them straight to Q7.56 keeps the monitor bit-identical to `rockwatch simulate --arith fixed`).
  const WallEngineOutput& process_wall(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2);
  void reset_wall(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2);
  // The wall's state restarts from rest (state unknown after a long gap or a publisher restart) but the alarm keeps
  // its level: a latched COLLAPSED stays latched, any other level falls only through the hold time.
  void restart_motion(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2);

  // The seam (SampleEngine): wall-frame doubles converted straight to Q7.56, then as reset_wall, restart_motion and
  // process_wall; the published quantities converted back to double.
  EngineSample start(double ug_mps2, double vg_mps2) override;
  EngineSample restart(double ug_mps2, double vg_mps2) override;
  EngineSample step(double ug_mps2, double vg_mps2) override;
  EngineSample step_at(double ug_mps2, double vg_mps2, std::int64_t t_us, std::int64_t step_us) override;
  std::uint32_t push_sensor(const core::WallSensorSample& sample) override;
  const core::ObserverCounters& observer_counters() const override { return observer_.counters(); }
  int finished_count() const override { return finished_count_; }
  const EngineSample& finished_sample(int i) const override { return finished_[i]; }
  int pending_samples() const override { return chain_.pending(); }
  void finish_pending() override;

  // Carry-over (core/work_meter.hpp): with a work budget (WallEngineConfig::work_budget_units > 0), step() and
  // step_at() queue the sample and work on the queue until the call's budget is spent; a sample whose
  // work does not fit finishes at a later call, bit-identical to process_wall(). At most kMaxFinishedPerCall samples
  // finish per call; at a full queue (WallEngineConfig::work_overflow, StepperAlarmChain::call) the engine sheds or
  // finishes the oldest sample beyond the budget (an overrun: flagged EngineSample::work_overrun, counted).
  static constexpr int kMaxFinishedPerCall = core::StepperAlarmChain<core::FixedRockingStepper>::kMaxFinishedPerCall;
  using WorkCounters = core::WorkTally;
  const WorkCounters& work_counters() const { return work_counters_; }
  std::int32_t work_budget_units() const { return work_budget_units_; }
  core::WorkOverflow work_overflow() const { return work_overflow_; }
  // Work units the last metered call spent, an overrun's included (the cost model's estimate of its work; m4-replay
  // compares it with the instructions counted).
  std::int32_t last_call_units() const { return last_call_units_; }

  // One sample through the stepper and, when enabled, the observer (t_us, step_us as step_at).
  const WallEngineOutput& process_wall_at(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2, std::int64_t t_us,
                                          std::int64_t step_us);
  bool observer_enabled() const { return observer_enabled_; }
  core::ObserverError observer_error() const { return observer_error_; }
  const core::WallObserver<core::FixedRockingStepper>& observer() const { return observer_; }
  const core::ObserverStepReport& last_observer_report() const { return observer_report_; }

  const core::FixedRockingStepper& stepper() const { return chain_.stepper(); }
  int substeps() const { return chain_.substeps(); }  // integration sub-steps per sample
  const WallEngineOutput& last() const { return out_; }
  core::FixedSetupError fixed_setup_error() const { return chain_.setup_error(); }

 private:
  EngineSample sample() const;
  // The seam's result: one sample finished in its own call.
  EngineSample finish_now();
  // The metered path of step()/step_at()/restart().
  // With the observer, t_us and step_us as step_at()'s.
  EngineSample step_metered(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2, bool restart, std::int64_t t_us,
                            std::int64_t step_us);
  void finish_queued(const core::AlarmChainOutput<core::FixedRockingStepper>& o, std::uint32_t tag);

  core::SensorAxes<core::AccelQ7_24> axes_{};
  core::StepperAlarmChain<core::FixedRockingStepper> chain_{};
  WallEngineOutput out_{};
  bool observer_enabled_ = false;
  core::ObserverError observer_error_ = core::ObserverError::ok;
  core::WallObserver<core::FixedRockingStepper> observer_{};
  core::ObserverStepReport observer_report_{};  // the observer's report of the last step (zero after start/restart)
  std::int32_t work_budget_units_ = 0;
  std::int32_t observer_budget_units_ = 0;  // with the observer: core::observer_work_budget_units(dt, caller overhead)
  core::WorkOverflow work_overflow_ = core::WorkOverflow::shed;
  std::int32_t last_call_units_ = 0;
  std::uint32_t calls_ = 0;  // metered calls so far: the tag of a queued sample
  EngineSample finished_[kMaxFinishedPerCall + 1]{};
  int finished_count_ = 0;
  WorkCounters work_counters_{};
};

}  // namespace rockwatch::firmware
