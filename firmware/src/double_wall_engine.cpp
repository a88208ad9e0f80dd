#include "rockwatch/firmware/double_wall_engine.hpp"

namespace rockwatch::firmware {

WallEngineError DoubleWallEngine::init(const WallEngineConfig& c) {
  const WallEngineError common = validate_wall_engine_config(c);
  if (common != WallEngineError::ok) return common;
  core::StepperOptions so;
  so.dt_s = c.dt_s;
  so.kappa = c.kappa;
  const core::StepperSetup<double> setup = core::make_stepper_setup(c.wall, c.model, c.r_energy, so);
  stepper_.init(setup);
  constants_ = core::make_instability_constants(setup, c.alarm);
  // The same step count as sim::analyse's AlarmRecorder for this step, so the hold time is the same.
  alarm_.init(core::hold_samples(c.alarm, c.dt_s));
  out_ = DoubleWallEngineOutput{};
  return WallEngineError::ok;
}

void DoubleWallEngine::reset_wall(double ug_mps2, double vg_mps2) {
  stepper_.reset(ug_mps2, vg_mps2);
  alarm_.reset();
  out_ = DoubleWallEngineOutput{};
}

const DoubleWallEngineOutput& DoubleWallEngine::process_wall(double ug_mps2, double vg_mps2) {
  out_.step = stepper_.step(ug_mps2, vg_mps2);
  out_.indicators = core::evaluate_instability(constants_, stepper_, out_.step);
  out_.alarm = alarm_.update(out_.indicators.conditions);
  return out_;
}

void DoubleWallEngine::restart_motion(double ug_mps2, double vg_mps2) {
  stepper_.reset(ug_mps2, vg_mps2);
  out_.step = core::StepReport<double>{};
  out_.indicators = core::evaluate_instability(constants_, stepper_, out_.step);
  out_.alarm = alarm_.update(out_.indicators.conditions);
}

}  // namespace rockwatch::firmware
