// The monitor's per-sample processing unit: a 3-axis accelerometer sample in, the wall's state and alarm out.
// Sensor axes (Eigen fixed size) → fixed-point rocking engine → instability indicators → alarm state machine.
// init() does all floating-point work and validation; process() then runs integer arithmetic only, allocates
// nothing and takes the same work every sample (bounded loops with fixed iteration counts). The monitor loop
// (issue 7) wraps it behind its transport; the embedded build (scripts/embedded-build.sh) compiles it for a
// Cortex-M4.
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
#include "rockwatch/core/wall.hpp"

namespace rockwatch::firmware {

using SensorSampleQ = Eigen::Matrix<core::AccelQ7_24, 3, 1>;  // sensor-frame acceleration [m/s²]

struct WallEngineConfig {
  core::WallParameters wall{};
  double r_energy = 0.0;           // restitution energy ratio r in [0, 1] [-]
  double kappa = 2.0;              // collapse at κ·x_inst [-]
  core::ModelKind model = core::ModelKind::linear;  // the fixed-point engine: linear only; DoubleWallEngine: either
  double dt_s = 0.005;             // sample interval = integration step [s]
  core::AlarmSettings alarm{};
  core::SensorAxes<double> axes = core::default_sensor_axes();
};

// Why init() refused a configuration. Values are stable: append, never renumber.
enum class WallEngineError : std::uint8_t {
  ok = 0,
  wall_invalid = 1,
  restitution_out_of_range = 2,
  kappa_out_of_range = 3,
  alarm_settings_invalid = 4,
  sensor_axes_invalid = 5,
  fixed_point_setup = 6,         // see fixed_setup_error()
  indicator_constants = 7,       // x_inst or ω outside the indicator formats
  model_not_supported = 8,       // the fixed-point engine runs the linear model only
};

const char* wall_engine_error_message(WallEngineError e);

// The checks both engines make (wall, r, κ, alarm settings, sensor axes): ok or the first failure.
WallEngineError validate_wall_engine_config(const WallEngineConfig& config);

struct WallEngineOutput {
  core::FixedStepReport step;                    // what the engine did inside the sample
  core::FixedInstabilityIndicators indicators;   // conditions, predicted time, energy ratio
  core::AlarmUpdate alarm;                       // level after the sample, reasons, transition flag
  core::AccelQ7_24 ug_mps2{};                    // the wall-frame inputs used [m/s²]
  core::AccelQ7_24 vg_mps2{};
};

class WallEngine {
 public:
  WallEngineError init(const WallEngineConfig& config);
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

  const core::FixedRockingStepper& stepper() const { return stepper_; }
  const WallEngineOutput& last() const { return out_; }
  core::FixedSetupError fixed_setup_error() const { return fixed_error_; }

 private:
  core::SensorAxes<core::AccelQ7_24> axes_{};
  core::FixedRockingStepper stepper_{};
  core::FixedInstabilityConstants constants_{};
  core::InstabilityAlarm alarm_{};
  WallEngineOutput out_{};
  core::FixedSetupError fixed_error_ = core::FixedSetupError::ok;
};

}  // namespace rockwatch::firmware
