#include "rockwatch/firmware/wall_engine.hpp"

namespace rockwatch::firmware {

const char* wall_engine_error_message(WallEngineError e) {
  switch (e) {
    case WallEngineError::ok: return "ok";
    case WallEngineError::wall_invalid: return "wall parameters are invalid";
    case WallEngineError::restitution_out_of_range: return "r must be in [0, 1]";
    case WallEngineError::kappa_out_of_range: return "kappa must be >= 1";
    case WallEngineError::alarm_settings_invalid:
      return "alarm settings invalid (lambda_w in (0, 1], hold in [0, 3600] s, energy margin in [1, 100], imminent "
             "horizon in [0, 10] s)";
    case WallEngineError::sensor_axes_invalid: return "sensor axes invalid (finite, |entries| <= 1.5, rows not zero)";
    case WallEngineError::fixed_point_setup: return "wall or step outside the fixed-point engine's formats";
    case WallEngineError::indicator_constants: return "x_inst must be in (0.008, 1.9) m for the alarm's formats";
    case WallEngineError::model_not_supported: return "the fixed-point engine runs the linear model only";
    case WallEngineError::observer_invalid: return "wall observer options invalid (see the observer error)";
    case WallEngineError::max_step_invalid:
      return "max_step_s must be > 0 s and give at most 64 sub-steps per sample (dt / max_step <= 64)";
    case WallEngineError::work_budget_invalid:
      return "work_budget_units must be 0 (no carry-over) or at least one sample with one located event, and "
             "the caller's units in [0, 1e9] (work_budget_units at least a sample's end with its publication)";
    case WallEngineError::work_overflow_invalid: return "work_overflow must be shed or finish";
  }
  return "?";
}

WallEngineError WallEngine::init(const WallEngineConfig& c) {
  observer_enabled_ = false;
  observer_error_ = core::ObserverError::ok;
  if (c.observer_enabled) observer_error_ = core::validate_observer_options(c.observer);
  const WallEngineError common = validate_wall_engine_config(c);
  if (common != WallEngineError::ok) return common;
  if (c.model != core::ModelKind::linear) return WallEngineError::model_not_supported;
  const int substeps = core::substeps_per_sample(c.dt_s, c.max_step_s);
  core::StepperOptions so;
  so.dt_s = c.dt_s / double(substeps);
  so.kappa = c.kappa;
  const core::StepperSetup<double> setup = core::make_stepper_setup(c.wall, core::ModelKind::linear, c.r_energy, so);
  switch (chain_.init(setup, c.alarm, c.dt_s, substeps)) {
    case core::AlarmChainError::ok: break;
    case core::AlarmChainError::substeps_out_of_range: return WallEngineError::max_step_invalid;
    case core::AlarmChainError::stepper_setup: return WallEngineError::fixed_point_setup;
    case core::AlarmChainError::indicator_constants: return WallEngineError::indicator_constants;
  }
  if (c.observer_enabled) {
    observer_error_ = observer_.init(c.observer, setup, c.wall);
    if (observer_error_ != core::ObserverError::ok) return WallEngineError::observer_invalid;
    observer_enabled_ = true;
  }
  axes_ = core::cast_sensor_axes<core::AccelQ7_24>(c.axes);
  work_budget_units_ = c.work_budget_units;
  observer_budget_units_ = core::observer_work_budget_units(c.dt_s, c.caller_overhead_units, c.caller_units_per_sample);
  chain_.set_caller_units_per_sample(c.caller_units_per_sample);
  work_overflow_ = c.work_overflow;
  calls_ = 0;
  finished_count_ = 0;
  work_counters_ = WorkCounters{};
  chain_.clear_pending();
  out_ = WallEngineOutput{};
  observer_report_ = core::ObserverStepReport{};
  return WallEngineError::ok;
}

void WallEngine::reset(const SensorSampleQ& sensor_mps2) {
  const Eigen::Matrix<core::AccelQ7_24, 2, 1> wall_inputs = core::wall_inputs(axes_, sensor_mps2);
  chain_.reset(core::wide_convert<core::AccelQ7_56>(wall_inputs(0)), core::wide_convert<core::AccelQ7_56>(wall_inputs(1)));
  out_ = WallEngineOutput{};
}

const WallEngineOutput& WallEngine::process(const SensorSampleQ& sensor_mps2) {
  const Eigen::Matrix<core::AccelQ7_24, 2, 1> wall_inputs = core::wall_inputs(axes_, sensor_mps2);
  out_.ug_mps2 = wall_inputs(0);
  out_.vg_mps2 = wall_inputs(1);
  chain_.step(core::wide_convert<core::AccelQ7_56>(out_.ug_mps2), core::wide_convert<core::AccelQ7_56>(out_.vg_mps2),
              out_);
  return out_;
}

const WallEngineOutput& WallEngine::process_wall(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2) {
  out_.ug_mps2 = core::wide_convert<core::AccelQ7_24>(ug_mps2);
  out_.vg_mps2 = core::wide_convert<core::AccelQ7_24>(vg_mps2);
  chain_.step(ug_mps2, vg_mps2, out_);
  return out_;
}

const WallEngineOutput& WallEngine::process_wall_at(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2,
                                                    std::int64_t t_us, std::int64_t step_us) {
  if (!observer_enabled_) return process_wall(ug_mps2, vg_mps2);
  out_.ug_mps2 = core::wide_convert<core::AccelQ7_24>(ug_mps2);
  out_.vg_mps2 = core::wide_convert<core::AccelQ7_24>(vg_mps2);
  observer_report_ = chain_.step_observed(ug_mps2, vg_mps2, observer_, t_us, step_us, out_);
  return out_;
}

// The wall at rest again: the observer's motion covariance follows; what it learned (ê, b̂), its queue and counters
// stay (init() starts a new observer).
void WallEngine::reset_wall(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2) {
  chain_.reset(ug_mps2, vg_mps2);
  out_ = WallEngineOutput{};
  if (observer_enabled_) observer_.restart_motion();
  observer_report_ = core::ObserverStepReport{};
}

void WallEngine::restart_motion(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2) {
  chain_.restart_motion(ug_mps2, vg_mps2, out_);
  if (observer_enabled_) observer_.restart_motion();
  observer_report_ = core::ObserverStepReport{};
}

// Straight to Q7.56: bit-identical to `rockwatch simulate --arith fixed` on the same doubles.
EngineSample WallEngine::start(double ug_mps2, double vg_mps2) {
  chain_.clear_pending();
  reset_wall(core::AccelQ7_56(ug_mps2), core::AccelQ7_56(vg_mps2));
  return finish_now();
}

EngineSample WallEngine::restart(double ug_mps2, double vg_mps2) {
  if (chain_.pending() > 0) return step_metered(core::AccelQ7_56(ug_mps2), core::AccelQ7_56(vg_mps2), true, 0, 0);
  restart_motion(core::AccelQ7_56(ug_mps2), core::AccelQ7_56(vg_mps2));
  return finish_now();
}

EngineSample WallEngine::step(double ug_mps2, double vg_mps2) {
  if (work_budget_units_ > 0 && !observer_enabled_) {
    return step_metered(core::AccelQ7_56(ug_mps2), core::AccelQ7_56(vg_mps2), false, 0, 0);
  }
  process_wall(core::AccelQ7_56(ug_mps2), core::AccelQ7_56(vg_mps2));
  return finish_now();
}

EngineSample WallEngine::step_at(double ug_mps2, double vg_mps2, std::int64_t t_us, std::int64_t step_us) {
  if (!observer_enabled_) return step(ug_mps2, vg_mps2);
  if (work_budget_units_ > 0) {
    return step_metered(core::AccelQ7_56(ug_mps2), core::AccelQ7_56(vg_mps2), false, t_us, step_us);
  }
  process_wall_at(core::AccelQ7_56(ug_mps2), core::AccelQ7_56(vg_mps2), t_us, step_us);
  return finish_now();
}

EngineSample WallEngine::finish_now() {
  finished_[0] = sample();
  finished_count_ = 1;
  return finished_[0];
}

// Carry-over (core/work_meter.hpp). The queue's samples are finished in order, each exactly as process_wall() would
// have; only the call that finishes it changes.
EngineSample WallEngine::step_metered(core::AccelQ7_56 ug_mps2, core::AccelQ7_56 vg_mps2, bool restart,
                                      std::int64_t t_us, std::int64_t step_us) {
  ++calls_;
  finished_count_ = 0;
  out_.ug_mps2 = core::wide_convert<core::AccelQ7_24>(ug_mps2);
  out_.vg_mps2 = core::wide_convert<core::AccelQ7_24>(vg_mps2);
  const auto on_sample = [this](const core::AlarmChainOutput<core::FixedRockingStepper>& o, std::uint32_t tag) {
    finish_queued(o, tag);
  };
  // With the observer its pieces are paid from the same meter and carried over with the samples (core/
  // stepper_alarm_chain.hpp, run_observed): the call's budget is the estimator's share of the sample.
  const auto report = observer_enabled_
                          ? chain_.call_observed(ug_mps2, vg_mps2, t_us, step_us, restart, observer_budget_units_,
                                                 work_overflow_, calls_, kMaxFinishedPerCall, observer_, on_sample)
                          : chain_.call(ug_mps2, vg_mps2, restart, work_budget_units_, work_overflow_, calls_,
                                        kMaxFinishedPerCall, on_sample);
  if (report.overrun) finished_[0].work_overrun = true;  // the overrun's sample is the call's first
  work_counters_.count_call(report);
  last_call_units_ = report.units_spent + report.overrun_units;
  if (finished_count_ > 0) return finished_[finished_count_ - 1];
  return sample();  // nothing finished: the state as it stands (the caller publishes only finished samples)
}

void WallEngine::finish_pending() {
  finished_count_ = 0;
  core::WorkMeter meter = core::WorkMeter::unlimited();  // the metered instantiation (one copy in the image)
  const auto on_sample = [this](const core::AlarmChainOutput<core::FixedRockingStepper>& o, std::uint32_t tag) {
    finish_queued(o, tag);
  };
  if (observer_enabled_) {
    chain_.run_observed(meter, observer_, kMaxFinishedPerCall, on_sample);
  } else {
    chain_.run(meter, kMaxFinishedPerCall,
               [](int, const core::FixedStepReport&, core::AccelQ7_56, core::AccelQ7_56) {}, on_sample);
  }
}

void WallEngine::finish_queued(const core::AlarmChainOutput<core::FixedRockingStepper>& o, std::uint32_t tag) {
  static_cast<core::AlarmChainOutput<core::FixedRockingStepper>&>(out_) = o;
  if (observer_enabled_) observer_report_ = chain_.observer_report();
  EngineSample& e = finished_[finished_count_++];
  e = sample();
  e.late_calls = static_cast<std::uint16_t>(calls_ - tag > 65535u ? 65535u : calls_ - tag);
  e.work_shed = o.step.work_shed;
  work_counters_.count_sample(calls_ - tag, e.work_shed);
}

std::uint32_t WallEngine::push_sensor(const core::WallSensorSample& sample) {
  return observer_enabled_ ? observer_.push(sample) : 0u;
}

EngineSample WallEngine::sample() const {
  const core::FixedRockingStepper& stepper = chain_.stepper();
  EngineSample e;
  e.x_m = stepper.x_m().to_double();
  e.xd_mps = stepper.xd_mps().to_double();
  e.energy_ratio = out_.indicators.energy_ratio.to_double();
  if (out_.indicators.t_valid) e.t_to_instability_s = out_.indicators.t_to_instability_s.to_double();
  e.side_positive = stepper.side() == core::Side::positive;
  e.moving = stepper.moving();
  e.input_invalid = out_.step.input_invalid;
  e.saturated = out_.step.saturated;
  e.alarm = out_.alarm;
  if (observer_enabled_) e.observer = core::observer_sample(observer_, observer_report_);
  return e;
}

}  // namespace rockwatch::firmware
