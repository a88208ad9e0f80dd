// The monitor's engine in double precision (`rockwatch-monitor --arith double`): the analysis engine of `rockwatch
// simulate --arith double` (core::RockingStepper<double>, double indicators, the same alarm) behind the interface of
// WallEngine's wall-frame path, so the monitor loop can run either. It supports the full model as well as the linear
// one.
//
// Why it exists: a lab that wants the monitor to agree with the double analysis to the last bit (or runs the full
// model) and has a host with an FPU. Its price: its work per sample is bounded (at most kMaxSegmentsPerStep
// segments) but not as even as the fixed-point engine's — the slowest sample measured is ~400 × the median
// (docs/BENCHMARKS.md) — and on a Cortex-M4F double is software-emulated. The fixed-point engine stays the default.
#pragma once

#include <cstdint>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/instability_indicators.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

namespace rockwatch::firmware {

struct DoubleWallEngineOutput {
  core::StepReport<double> step;                       // what the engine did inside the sample
  core::InstabilityIndicators<double> indicators;      // conditions, predicted time, energy ratio
  core::AlarmUpdate alarm;                             // level after the sample, reasons, transition flag
};

class DoubleWallEngine {
 public:
  // The same validation and error codes as WallEngine::init (fixed-point format limits excepted); config.model may
  // be full.
  WallEngineError init(const WallEngineConfig& config);
  // Wall at rest, alarm QUIET, with this sample as the current input (no step).
  void reset_wall(double ug_mps2, double vg_mps2);
  // One sample in the wall's frame [m/s²]: one engine step, the indicators, the alarm. Bounded work; no allocation.
  const DoubleWallEngineOutput& process_wall(double ug_mps2, double vg_mps2);
  // As WallEngine::restart_motion: the state restarts from rest, the alarm keeps its level.
  void restart_motion(double ug_mps2, double vg_mps2);

  const core::RockingStepper<double>& stepper() const { return stepper_; }
  const DoubleWallEngineOutput& last() const { return out_; }

 private:
  core::RockingStepper<double> stepper_{};
  core::InstabilityConstants<double> constants_{};
  core::InstabilityAlarm alarm_{};
  DoubleWallEngineOutput out_{};
};

}  // namespace rockwatch::firmware
