// The monitor's per-sample processing unit: a 3-axis accelerometer sample in, the wall's state and alarm out.
// Sensor axes (Eigen fixed size) → core::StepperAlarmChain over the fixed-point rocking stepper (stepper →
// instability indicators → alarm state machine). init() does all floating-point work and validation; process() then
// runs integer arithmetic only, allocates nothing and takes the same work every sample (bounded loops with fixed
// iteration counts). With the observer enabled (WallEngineConfig::observer_enabled), core::WallObserver over the same
// fixed-point stepper (scalar ObserverQ10_53) corrects the state between the stepper and the indicators: its work is
// bounded too (at most kQueueCapacity scalar updates per sample). It is the firmware's SampleEngine: the monitor loop runs it behind that seam; the embedded
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

  core::SensorAxes<core::AccelQ7_24> axes_{};
  core::StepperAlarmChain<core::FixedRockingStepper> chain_{};
  WallEngineOutput out_{};
  bool observer_enabled_ = false;
  core::ObserverError observer_error_ = core::ObserverError::ok;
  core::WallObserver<core::FixedRockingStepper> observer_{};
  core::ObserverStepReport observer_report_{};  // the observer's report of the last step (zero after start/restart)
};

}  // namespace rockwatch::firmware
