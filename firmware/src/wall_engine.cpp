#include "rockwatch/firmware/wall_engine.hpp"

namespace rockwatch::firmware {

const char* wall_engine_error_message(WallEngineError e) {
  switch (e) {
    case WallEngineError::ok: return "ok";
    case WallEngineError::wall_invalid: return "wall parameters are invalid";
    case WallEngineError::restitution_out_of_range: return "r must be in [0, 1]";
    case WallEngineError::kappa_out_of_range: return "kappa must be >= 1";
    case WallEngineError::alarm_settings_invalid:
      return "alarm settings invalid (lambda_w in (0, 1], hold in [0, 3600] s, energy margin in [1, 100])";
    case WallEngineError::sensor_axes_invalid: return "sensor axes invalid (finite, |entries| <= 1.5, rows not zero)";
    case WallEngineError::fixed_point_setup: return "wall or step outside the fixed-point engine's formats";
    case WallEngineError::indicator_constants: return "x_inst must be in (0.008, 1.9) m for the alarm's formats";
    case WallEngineError::model_not_supported: return "the fixed-point engine runs the linear model only";
  }
  return "?";
}

WallEngineError validate_wall_engine_config(const WallEngineConfig& c) {
  if (!core::validate_wall(c.wall).ok()) return WallEngineError::wall_invalid;
  if (!(c.r_energy >= 0.0 && c.r_energy <= 1.0)) return WallEngineError::restitution_out_of_range;
  if (!(c.kappa >= 1.0 && c.kappa < 100.0)) return WallEngineError::kappa_out_of_range;
  if (!core::alarm_settings_valid(c.alarm)) return WallEngineError::alarm_settings_invalid;
  if (!core::sensor_axes_valid(c.axes)) return WallEngineError::sensor_axes_invalid;
  return WallEngineError::ok;
}

WallEngineError WallEngine::init(const WallEngineConfig& c) {
  const WallEngineError common = validate_wall_engine_config(c);
  if (common != WallEngineError::ok) return common;
  if (c.model != core::ModelKind::linear) return WallEngineError::model_not_supported;
  core::StepperOptions so;
  so.dt_s = c.dt_s;
  so.kappa = c.kappa;
  const core::StepperSetup<double> setup = core::make_stepper_setup(c.wall, core::ModelKind::linear, c.r_energy, so);
  fixed_error_ = stepper_.init(setup);
  if (fixed_error_ != core::FixedSetupError::ok) return WallEngineError::fixed_point_setup;
  if (!core::make_fixed_instability_constants(setup, c.alarm, constants_)) return WallEngineError::indicator_constants;
  axes_ = core::cast_sensor_axes<core::AccelQ7_24>(c.axes);
  alarm_.init(core::hold_samples(c.alarm, c.dt_s));
  out_ = WallEngineOutput{};
  return WallEngineError::ok;
}

void WallEngine::reset(const SensorSampleQ& sensor_mps2) {
  const Eigen::Matrix<core::AccelQ7_24, 2, 1> wall_inputs = core::wall_inputs(axes_, sensor_mps2);
  stepper_.reset(core::wide_convert<core::AccelQ7_56>(wall_inputs(0)), core::wide_convert<core::AccelQ7_56>(wall_inputs(1)));
  alarm_.reset();
  out_ = WallEngineOutput{};
}

const WallEngineOutput& WallEngine::process(const SensorSampleQ& sensor_mps2) {
  const Eigen::Matrix<core::AccelQ7_24, 2, 1> wall_inputs = core::wall_inputs(axes_, sensor_mps2);
  out_.ug_mps2 = wall_inputs(0);
  out_.vg_mps2 = wall_inputs(1);
  out_.step = stepper_.step(core::wide_convert<core::AccelQ7_56>(out_.ug_mps2),
                            core::wide_convert<core::AccelQ7_56>(out_.vg_mps2));
  out_.indicators = core::evaluate_instability(constants_, stepper_, out_.step);
  out_.alarm = alarm_.update(out_.indicators.conditions);
  return out_;
}

const WallEngineOutput& WallEngine::process_wall(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2) {
  out_.ug_mps2 = core::wide_convert<core::AccelQ7_24>(ug_mps2);
  out_.vg_mps2 = core::wide_convert<core::AccelQ7_24>(vg_mps2);
  out_.step = stepper_.step(ug_mps2, vg_mps2);
  out_.indicators = core::evaluate_instability(constants_, stepper_, out_.step);
  out_.alarm = alarm_.update(out_.indicators.conditions);
  return out_;
}

void WallEngine::reset_wall(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2) {
  stepper_.reset(ug_mps2, vg_mps2);
  alarm_.reset();
  out_ = WallEngineOutput{};
}

void WallEngine::restart_motion(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2) {
  stepper_.reset(ug_mps2, vg_mps2);
  out_.step = core::FixedStepReport{};
  out_.indicators = core::evaluate_instability(constants_, stepper_, out_.step);
  out_.alarm = alarm_.update(out_.indicators.conditions);
}

}  // namespace rockwatch::firmware
