#include "rockwatch/sim/double_wall_engine.hpp"

namespace rockwatch::sim {

using core::EngineSample;
using core::WallEngineError;

WallEngineError DoubleWallEngine::init(const core::WallEngineConfig& c) {
  observer_enabled_ = false;
  observer_error_ = core::ObserverError::ok;
  if (c.observer_enabled) observer_error_ = core::validate_observer_options(c.observer);
  const WallEngineError common = core::validate_wall_engine_config(c);
  if (common != WallEngineError::ok) return common;
  const int substeps = core::substeps_per_sample(c.dt_s, c.max_step_s);
  core::StepperOptions so;
  so.dt_s = c.dt_s / double(substeps);
  so.kappa = c.kappa;
  const core::StepperSetup<double> setup = core::make_stepper_setup(c.wall, c.model, c.r_energy, so);
  // The same sub-steps and hold in samples as sim::analyse for this sample interval. The double chain cannot refuse
  // a valid configuration.
  chain_.init(setup, c.alarm, c.dt_s, substeps);
  if (c.observer_enabled) {
    observer_error_ = observer_.init(c.observer, setup, c.wall);
    if (observer_error_ != core::ObserverError::ok) return WallEngineError::observer_invalid;
    observer_enabled_ = true;
  }
  out_ = DoubleWallEngineOutput{};
  observer_report_ = core::ObserverStepReport{};
  return WallEngineError::ok;
}

// As firmware::WallEngine: the observer's motion restarts with the wall's, what it learned stays.
EngineSample DoubleWallEngine::start(double ug_mps2, double vg_mps2) {
  chain_.reset(ug_mps2, vg_mps2);
  out_ = DoubleWallEngineOutput{};
  if (observer_enabled_) observer_.restart_motion();
  observer_report_ = core::ObserverStepReport{};
  return last_ = sample();
}

EngineSample DoubleWallEngine::restart(double ug_mps2, double vg_mps2) {
  chain_.restart_motion(ug_mps2, vg_mps2, out_);
  if (observer_enabled_) observer_.restart_motion();
  observer_report_ = core::ObserverStepReport{};
  return last_ = sample();
}

EngineSample DoubleWallEngine::step_at(double ug_mps2, double vg_mps2, std::int64_t t_us, std::int64_t step_us) {
  if (!observer_enabled_) return step(ug_mps2, vg_mps2);
  observer_report_ = chain_.step_observed(ug_mps2, vg_mps2, observer_, t_us, step_us, out_);
  return last_ = sample();
}

std::uint32_t DoubleWallEngine::push_sensor(const core::WallSensorSample& sample) {
  return observer_enabled_ ? observer_.push(sample) : 0u;
}

EngineSample DoubleWallEngine::step(double ug_mps2, double vg_mps2) {
  chain_.step(ug_mps2, vg_mps2, out_);
  return last_ = sample();
}

EngineSample DoubleWallEngine::sample() const {
  const core::RockingStepper<double>& stepper = chain_.stepper();
  EngineSample e;
  e.x_m = stepper.state().x_m;
  e.xd_mps = stepper.state().xd_mps;
  e.energy_ratio = out_.indicators.energy_ratio;
  if (out_.indicators.t_valid) e.t_to_instability_s = out_.indicators.t_to_instability_s;
  e.side_positive = stepper.side() == core::Side::positive;
  e.moving = stepper.moving();
  e.input_invalid = out_.step.input_invalid;
  e.alarm = out_.alarm;
  if (observer_enabled_) e.observer = core::observer_sample(observer_, observer_report_);
  return e;
}

}  // namespace rockwatch::sim
