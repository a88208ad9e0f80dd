// The monitor's engine in double precision (`rockwatch-monitor --arith double`): the chain of `rockwatch simulate
// --arith double` (core::StepperAlarmChain over core::RockingStepper<double>: stepper, double indicators, the same
// alarm) behind the monitor loop's engine seam (core::SampleEngine), so the monitor loop can run it. It supports the
// full model as well as the linear one. Host code: firmware never includes this header.
//
// Why it exists: a lab that wants the monitor to agree with the double analysis to the last bit (or runs the full
// model) and has a host with an FPU. Its price: its work per sample is bounded (the chatter rule: at most
// kMaxImpactsPerSubstep impacts located per sub-step, SPEC §3) but not as even as the fixed-point engine's — the slowest sample measured is ~400 × the median
// (docs/BENCHMARKS.md) — and on a Cortex-M4F double is software-emulated. The fixed-point engine stays the default.
#pragma once

#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/core/sample_engine.hpp"

namespace rockwatch::sim {

using DoubleWallEngineOutput = core::AlarmChainOutput<core::RockingStepper<double>>;

class DoubleWallEngine final : public core::SampleEngine {
 public:
  core::MonitorArithmetic arithmetic() const override { return core::MonitorArithmetic::double_precision; }
  // The same validation and error codes as firmware::WallEngine::init (fixed-point format limits excepted);
  // config.model may be full. The sensor axes are validated but not used (the input is in the wall's frame).
  core::WallEngineError init(const core::WallEngineConfig& config) override;
  // Wall at rest, alarm QUIET, with this sample as the current input (no step).
  core::EngineSample start(double ug_mps2, double vg_mps2) override;
  // The state restarts from rest, the alarm keeps its level.
  core::EngineSample restart(double ug_mps2, double vg_mps2) override;
  // One sample in the wall's frame [m/s²]: one engine step, the indicators, the alarm. Bounded work; no allocation.
  core::EngineSample step(double ug_mps2, double vg_mps2) override;
  // With the observer enabled: core::WallObserver over the double stepper between the step and the indicators.
  core::EngineSample step_at(double ug_mps2, double vg_mps2, std::int64_t t_us, std::int64_t step_us) override;
  std::uint32_t push_sensor(const core::WallSensorSample& sample) override;
  const core::ObserverCounters& observer_counters() const override { return observer_.counters(); }
  // Every sample finishes in its own call.
  int finished_count() const override { return 1; }
  const core::EngineSample& finished_sample(int) const override { return last_; }
  int pending_samples() const override { return 0; }
  void finish_pending() override {}
  bool observer_enabled() const { return observer_enabled_; }
  core::ObserverError observer_error() const { return observer_error_; }
  const core::WallObserver<core::RockingStepper<double>>& observer() const { return observer_; }

  const core::RockingStepper<double>& stepper() const { return chain_.stepper(); }
  const DoubleWallEngineOutput& last() const { return out_; }

 private:
  core::EngineSample sample() const;

  core::StepperAlarmChain<core::RockingStepper<double>> chain_{};
  DoubleWallEngineOutput out_{};
  bool observer_enabled_ = false;
  core::ObserverError observer_error_ = core::ObserverError::ok;
  core::WallObserver<core::RockingStepper<double>> observer_{};
  core::ObserverStepReport observer_report_{};
  core::EngineSample last_{};  // what the last call returned
};

}  // namespace rockwatch::sim
