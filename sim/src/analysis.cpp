#include "rockwatch/sim/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <type_traits>
#include <vector>

#include "analysis_engines.hpp"
#include "rockwatch/core/rocking_stepper.hpp"

namespace rockwatch::sim {

using core::Side;

double peak_abs(const std::vector<double>& v) {
  double peak = 0.0;
  for (double a : v) peak = std::max(peak, std::fabs(a));
  return peak;
}

namespace {

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Each setting on its own (core's validators), so the message names the one at fault.
void check_alarm_settings(const core::AlarmSettings& a) {
  if (!core::lambda_warning_valid(a.lambda_warning)) {
    throw AnalysisError("alarm lambda_warning must be in (0, 1] (got " + number_text(a.lambda_warning) + ")");
  }
  if (!core::hold_valid(a.hold_s)) {
    throw AnalysisError("alarm hold_s must be in [0, 3600] s (got " + number_text(a.hold_s) + ")");
  }
  if (!core::energy_margin_valid(a.energy_margin)) {
    throw AnalysisError("alarm energy_margin must be in [1, 100] (got " + number_text(a.energy_margin) + ")");
  }
  if (!core::alarm_settings_valid(a)) throw AnalysisError("alarm settings are invalid");  // a bound added in core
}

void check_options(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o) {
  const core::WallCheck wc = core::validate_wall(wall);
  if (!wc.ok()) throw AnalysisError(std::string("wall parameter ") + wc.field + " " + wc.message);
  if (!core::restitution_valid(o.restitution)) throw AnalysisError("restitution r must be in [0, 1]");
  if (!(std::isfinite(o.kappa) && o.kappa >= 1.0)) throw AnalysisError("kappa must be a finite number >= 1");
  if (!(std::isfinite(o.max_step_s) && o.max_step_s > 0.0)) throw AnalysisError("max step must be > 0 s");
  if (std::isfinite(motion.dt_s) && motion.dt_s > 0.0 && core::substeps_per_sample(motion.dt_s, o.max_step_s) == 0) {
    throw AnalysisError("max step " + number_text(o.max_step_s) + " s would need more than " +
                        std::to_string(core::kMaxSubsteps) + " sub-steps per record sample (dt " +
                        number_text(motion.dt_s) + " s): choose max step >= dt / " +
                        std::to_string(core::kMaxSubsteps));
  }
  if (o.t_end_s && !(std::isfinite(*o.t_end_s) && *o.t_end_s >= 0.0)) throw AnalysisError("t_end must be >= 0 s");
  if (o.initial_x_m && !(std::isfinite(*o.initial_x_m) && std::fabs(*o.initial_x_m) <= 1.0)) {
    throw AnalysisError("initial displacement x0 must be a finite number of metres with |x0| <= 1 m");
  }
  if (!(std::isfinite(motion.dt_s) && motion.dt_s > 0.0)) throw AnalysisError("record dt must be > 0 s");
  if (motion.ug_mps2.size() < 2) throw AnalysisError("record must hold at least two samples");
  if (!motion.vg_mps2.empty() && motion.vg_mps2.size() != motion.ug_mps2.size()) {
    throw AnalysisError("vertical record must have as many samples as the horizontal one on the same time grid");
  }
  for (std::size_t i = 0; i < motion.ug_mps2.size(); ++i) {
    if (!std::isfinite(motion.ug_mps2[i])) {
      std::ostringstream m;
      m << "horizontal sample " << i << " (t = " << double(i) * motion.dt_s << " s) is not finite";
      throw AnalysisError(m.str());
    }
  }
  for (std::size_t i = 0; i < motion.vg_mps2.size(); ++i) {
    const double v = motion.vg_mps2[i];
    if (!std::isfinite(v) || !(wall.g_mps2 + v > 0.0)) {
      std::ostringstream m;
      m << "vertical sample " << i << " (t = " << double(i) * motion.dt_s << " s) is " << v
        << " m/s2: G = g + v'' must stay > 0 (lift-off is outside the model)";
      throw AnalysisError(m.str());
    }
  }
  if (o.evaluate_alarm) check_alarm_settings(o.alarm);
  if (o.wall_sensors) {
    const core::ObserverError err = core::validate_observer_options(o.observer);
    if (err != core::ObserverError::ok) throw AnalysisError(core::observer_error_message(err));
    if (o.observer_r_after_impacts < 0) throw AnalysisError("observer_r_after_impacts must be >= 0");
    const std::vector<core::WallSensorSample>& samples = *o.wall_sensors;
    for (std::size_t i = 1; i < samples.size(); ++i) {
      if (samples[i].utime_us < samples[i - 1].utime_us) {
        std::ostringstream m;
        m << "wall sensor sample " << i << " (utime " << samples[i].utime_us << " us) comes before sample " << i - 1
          << " (utime " << samples[i - 1].utime_us << " us): the samples must be in time order";
        throw AnalysisError(m.str());
      }
    }
  }
  if (o.arithmetic == Arithmetic::fixed_point && o.model != core::ModelKind::linear) {
    throw AnalysisError("fixed-point arithmetic supports the linear model only");
  }
}

// Collects the summary from the engine's per-step reports (either arithmetic: values in double).
class ResponseRecorder {
 public:
  ResponseRecorder(const core::WallParameters& wall, const AnalysisOptions& o, AnalysisResult& r)
      : wall_(wall), options_(o), result_(r) {}

  template <typename Engine>
  void row(double t_s, double ug, double vg, const Engine& e) {
    const double x = e.x_m();
    const double ax = std::fabs(x);
    if (ax > result_.max_abs_x_m) {
      result_.max_abs_x_m = ax;
      result_.t_max_abs_x_s = t_s;
    }
    if (options_.keep_history) {
      result_.history.push_back(HistoryRow{t_s, ug, vg, x, e.xd_mps(), e.xdd_mps2(), -x / wall_.h1_m, x / wall_.h2_m,
                                           e.stepper().side() == Side::positive ? 1 : -1});
    }
  }

  // Returns the time the state now stands at: the step end, or the collapse point.
  template <typename Report>
  double events(double t0_s, double h_s, const Report& rep) {
    using detail::to_double;
    if (rep.started && !result_.t_first_motion_s) result_.t_first_motion_s = t0_s + to_double(rep.start_fraction) * h_s;
    if (rep.impacts_total > 0 && result_.impacts.size() < options_.max_impacts_kept) {
      result_.impacts.push_back(ImpactEvent{t0_s + to_double(rep.first_impact_fraction) * h_s,
                                            to_double(rep.first_impact_v_before_mps),
                                            to_double(rep.first_impact_v_after_mps)});
    }
    if (options_.mark_counted_impact > 0 && !result_.t_counted_impact_s &&
        result_.n_impacts + rep.impacts_counted >= options_.mark_counted_impact) {
      result_.t_counted_impact_s = t0_s + to_double(rep.first_impact_fraction) * h_s;  // in this sub-step
    }
    result_.n_impacts += rep.impacts_counted;
    result_.n_impacts_total += rep.impacts_total;
    if (rep.exceeded && !result_.t_exceed_s) result_.t_exceed_s = t0_s + to_double(rep.exceed_fraction) * h_s;
    if (rep.collapsed) {
      result_.t_collapse_s = t0_s + to_double(rep.collapse_fraction) * h_s;
      return *result_.t_collapse_s;
    }
    return t0_s + h_s;
  }

 private:
  const core::WallParameters& wall_;
  const AnalysisOptions& options_;
  AnalysisResult& result_;
};

// The wall observer of an analysis with wall sensors (AnalysisOptions::wall_sensors): hands it the samples due by
// each step end, runs the step through the chain's step_observed (stepper → observer → indicators → alarm) and
// keeps what the summary reports. The samples are pushed only when due (utime ≤ the step end), in order, so the
// observer's queue holds only those it applies in this step; a future sample is never seen.
template <typename Engine>
class ObservedSteps {
 public:
  using Observer = core::WallObserver<typename Engine::Stepper>;

  ObservedSteps(const core::WallParameters& wall, const core::StepperSetup<double>& setup, const AnalysisOptions& o,
                double dt_s)
      : samples_(*o.wall_sensors), r_after_impacts_(o.observer_r_after_impacts),
        rocking_peak_m_(o.observer.inform_peak_noises * o.observer.x_noise_m),
        estimate_before_s_(o.observer_estimate_before_s),
        step_us_(static_cast<std::int64_t>(std::llround(dt_s * 1e6))) {
    const core::ObserverError err = observer_.init(o.observer, setup, wall);
    if (err != core::ObserverError::ok) throw AnalysisError(core::observer_error_message(err));
  }

  // The sample interval from t0_s to t0_s + dt_s (its end, in whole µs, is the observer's clock): the samples due
  // by its end are queued (the observer applies each only once a sub-step reaches its time), then the chain's
  // sub-steps run through the observer; on_substep as StepperAlarmChain::step_observed.
  template <typename OnSubstep>
  void step(Engine& engine, typename Engine::Input ug, typename Engine::Input vg, double t0_s, double dt_s,
            OnSubstep&& on_substep) {
    const std::int64_t t_us = core::observed_step_end_us(t0_s, dt_s);
    while (next_ < samples_.size() && samples_[next_].utime_us <= t_us) observer_.push(samples_[next_++]);
    before_step_ = estimates();
    if (estimate_before_s_ && !before_time_ && t0_s + dt_s > *estimate_before_s_) before_time_ = before_step_;
    const core::ObserverStepReport outcome =
        engine.chain().step_observed(ug, vg, observer_, t_us, step_us_, engine.out(), on_substep);
    flags_ |= outcome.flags;
    last_flags_ = outcome.flags;
    if (outcome.flags & core::observer_flag::sensor_lost) ++steps_lost_;
  }

  // The estimates at the end of the sample (AnalysisResult::observer_history), with the fused state x, ẋ then.
  ObserverHistoryRow history_row(double t_s, double x_m, double xd_mps) const {
    ObserverHistoryRow row{t_s,
                           observer_.sigma_x_m(),
                           observer_.sigma_xd_mps(),
                           observer_.sqrt_r_estimate(),
                           observer_.capacity_scale(),
                           observer_.stiffness_scale(),
                           (last_flags_ & core::observer_flag::x_active) != 0};
    row.x_m = x_m;
    row.xd_mps = xd_mps;
    row.r = observer_.r_estimate();
    row.sigma_r = observer_.sigma_r();
    row.x_inst_m = observer_.x_inst_estimate_m();
    row.sigma_x_inst_m = observer_.sigma_x_inst_m();
    row.flags = last_flags_;
    return row;
  }

  // After the step's events (counted impacts before and after it): keeps r̂ as it stood before the step in which
  // impact number r_after_impacts + 1 happened. abs_x_m: |x| at the end of the sub-step, for the rocking impacts:
  // those after a half-cycle whose |x| peaked at ≥ inform_peak_noises × x_noise (the size from which the observer
  // learns √r, SPEC §8); r̂ likewise before rocking impact number r_after_impacts + 1.
  void impacts(int before, int after, double abs_x_m) {
    if (after > before) {
      if (!after_impacts_ && before >= r_after_impacts_) after_impacts_ = before_step_;
      if (half_cycle_peak_m_ >= rocking_peak_m_) {
        if (!after_rocking_ && rocking_impacts_ >= r_after_impacts_) after_rocking_ = before_step_;
        ++rocking_impacts_;
      }
      half_cycle_peak_m_ = 0.0;
    }
    if (abs_x_m > half_cycle_peak_m_) half_cycle_peak_m_ = abs_x_m;
  }

  void summarise(ObserverSummary& s, int n_impacts) const {
    s.evaluated = true;
    s.r_estimate = observer_.r_estimate();
    s.sigma_r = observer_.sigma_r();
    s.bias_estimate_m = observer_.bias_m();
    s.sigma_bias_m = observer_.sigma_bias_m();
    s.x_noise_m = observer_.x_noise_m();
    s.x_noise_readings = observer_.x_noise_readings();
    s.sigma_x_m = observer_.sigma_x_m();
    s.x_rms_innovation_m = observer_.rms_innovation_x_m();
    s.counters = observer_.counters();
    s.n_updates = s.counters.x_updates;
    s.n_accel_updates = s.counters.a_updates;
    s.n_rejected = s.counters.rejected;
    s.flags_seen = flags_;
    s.samples_given = samples_.size();
    s.samples_pushed = next_;
    s.steps_sensor_lost = steps_lost_;
    s.x_inst_estimate_m = observer_.x_inst_estimate_m();
    s.sigma_x_inst_m = observer_.sigma_x_inst_m();
    s.omega_estimate_rps = observer_.omega_estimate_rps();
    s.sigma_omega_rps = observer_.sigma_omega_rps();
    s.c_estimate_mps2 = observer_.c_estimate_mps2();
    s.sigma_c_mps2 = observer_.sigma_c_mps2();
    s.k_estimate_ps2 = observer_.k_estimate_ps2();
    s.sigma_k_ps2 = observer_.sigma_k_ps2();
    s.barrier_estimate_m2ps2 = observer_.barrier_estimate_m2ps2();
    s.capacity_scale = observer_.capacity_scale();
    s.sigma_capacity_scale = observer_.sigma_capacity_scale();
    s.stiffness_scale = observer_.stiffness_scale();
    s.sigma_stiffness_scale = observer_.sigma_stiffness_scale();
    // After the counted (or rocking) impacts: as they stood before the next one, or at the end when there was no
    // next one.
    const std::optional<Estimates> after_impacts =
        after_impacts_ ? after_impacts_ : n_impacts >= r_after_impacts_ ? std::optional(estimates()) : std::nullopt;
    if (after_impacts) {
      s.r_estimate_after_impacts = after_impacts->r;
      s.sigma_r_after_impacts = after_impacts->sigma_r;
      s.x_inst_estimate_after_impacts_m = after_impacts->x_inst_m;
      s.sigma_x_inst_after_impacts_m = after_impacts->sigma_x_inst_m;
    }
    s.rocking_impacts = rocking_impacts_;
    const std::optional<Estimates> after_rocking =
        after_rocking_ ? after_rocking_
                       : rocking_impacts_ >= r_after_impacts_ ? std::optional(estimates()) : std::nullopt;
    if (after_rocking) {
      s.r_estimate_after_rocking_impacts = after_rocking->r;
      s.sigma_r_after_rocking_impacts = after_rocking->sigma_r;
    }
    if (before_time_) {
      s.r_estimate_before_time = before_time_->r;
      s.x_inst_estimate_before_time_m = before_time_->x_inst_m;
    }
  }

 private:
  // r̂ and x̂_inst with the σ published with them, at one moment.
  struct Estimates {
    double r, sigma_r, x_inst_m, sigma_x_inst_m;
  };
  Estimates estimates() const {
    return Estimates{observer_.r_estimate(), observer_.sigma_r(), observer_.x_inst_estimate_m(),
                     observer_.sigma_x_inst_m()};
  }

  const std::vector<core::WallSensorSample>& samples_;
  int r_after_impacts_;
  double rocking_peak_m_;  // a rocking impact follows a half-cycle whose |x| peaked at least this [m]
  std::optional<double> estimate_before_s_;
  std::optional<Estimates> before_time_;
  std::int64_t step_us_;
  Observer observer_{};
  std::size_t next_ = 0;
  std::uint32_t flags_ = 0;       // every step's flags, or-ed
  std::uint32_t last_flags_ = 0;  // the last step's
  std::size_t steps_lost_ = 0;
  Estimates before_step_{};                        // as they stood before the current step
  std::optional<Estimates> after_impacts_, after_rocking_;  // before counted / rocking impact r_after_impacts + 1
  double half_cycle_peak_m_ = 0.0;
  int rocking_impacts_ = 0;
};

// One input sample of the engine: the chain's sub-steps to the input (ug, vg), each followed by its events and row
// (at the time the state stands at: the sub-step's end or the collapse point); then, when evaluated, the alarm
// update once per sample, at the time the state stands at after its last sub-step. The indicators run when the alarm
// is evaluated or the engine's verdict needs them. With an observer the sub-steps go through it (the indicators then
// always run).
template <typename Engine>
void analysis_sample(Engine& engine, typename Engine::Input ug, typename Engine::Input vg, double t0_s, double dt_s,
                     double h_s, const AnalysisOptions& o, ResponseRecorder& recorder, AnalysisResult& result,
                     ObservedSteps<Engine>* observed) {
  using detail::to_double;
  using Input = typename Engine::Input;
  auto& out = engine.out();
  double t_s = t0_s + dt_s;
  const auto on_substep = [&](int j, const auto& sub, Input ug_j, Input vg_j) {
    const int impacts_before = result.n_impacts;
    if (Engine::saturated(sub)) result.saturated = true;
    t_s = recorder.events(t0_s + double(j - 1) * h_s, h_s, sub);
    if (observed) observed->impacts(impacts_before, result.n_impacts, std::fabs(engine.x_m()));
    recorder.row(t_s, to_double(ug_j), to_double(vg_j), engine);
  };
  if (observed) {
    observed->step(engine, ug, vg, t0_s, dt_s, on_substep);
    if (o.keep_history) result.observer_history.push_back(observed->history_row(t_s, engine.x_m(), engine.xd_mps()));
  } else {
    engine.chain().step_motion(ug, vg, out, on_substep);
    if (o.evaluate_alarm || Engine::kVerdictNeedsIndicators) engine.chain().evaluate(out);
  }
  if (!o.evaluate_alarm) return;
  detail::AlarmSample sample;
  sample.x_m = engine.x_m();
  sample.xd_mps = engine.xd_mps();
  if (out.indicators.t_valid) sample.t_to_instability_s = to_double(out.indicators.t_to_instability_s);
  sample.energy_ratio = to_double(out.indicators.energy_ratio);
  detail::record_alarm_update(result.alarm, o.max_alarm_transitions_kept, t_s, out.alarm, sample);
}

// The record's sample i, zero past its end.
inline double sample_or_zero(const std::vector<double>& v, std::size_t i) { return i < v.size() ? v[i] : 0.0; }

// The one analysis loop, for either engine: forced motion over the record (to t_end), then free motion until the
// engine's verdict says safe, or collapse, or the free-motion limit (SPEC §4.3). Input sample by sample, each
// integrated in start.n_sub sub-steps (the input linear between samples, zero samples after the record).
template <typename Engine>
AnalysisResult run_analysis(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o) {
  using detail::to_double;
  Engine::check_motion(motion);
  AnalysisResult result;
  result.arithmetic = Engine::kArithmetic;
  const detail::AnalysisStart start = detail::start_analysis(wall, motion, o, result);
  const double h = start.h_s, dt = motion.dt_s;
  Engine engine(wall, start.setup, o, dt, start.n_sub);
  if (o.evaluate_alarm) result.alarm.evaluated = true;
  std::optional<ObservedSteps<Engine>> observed;
  if (o.wall_sensors) observed.emplace(wall, start.setup, o, dt);
  ObservedSteps<Engine>* const observer = observed ? &*observed : nullptr;

  // Every input the engine is given, in double, when asked (AnalysisOptions::engine_inputs_out).
  // And, to measure the monitor's latency (AnalysisOptions::work_budget_units), in the engine's format.
  constexpr bool kFixed = std::is_same_v<Engine, detail::FixedAnalysisEngine>;
  const bool measure = o.work_budget_units > 0 && o.evaluate_alarm && !o.wall_sensors && kFixed;  // not a constant: captured
  std::vector<std::array<core::AccelQ7_56, 2>> fed;
  const auto note_input = [&o, &fed, measure](double ug, double vg) {
    if (o.engine_inputs_out) o.engine_inputs_out->push_back({ug, vg});
    if (measure) fed.push_back({core::AccelQ7_56(ug), core::AccelQ7_56(vg)});
  };
  note_input(sample_or_zero(motion.ug_mps2, 0), sample_or_zero(motion.vg_mps2, 0));
  const typename Engine::Input ug0 = Engine::input(sample_or_zero(motion.ug_mps2, 0));
  const typename Engine::Input vg0 = Engine::input(sample_or_zero(motion.vg_mps2, 0));
  if (o.initial_x_m) {
    engine.chain().reset_released(typename Engine::Length(*o.initial_x_m), typename Engine::Speed(0.0), ug0, vg0);
  } else {
    engine.chain().reset(ug0, vg0);
  }
  const auto forced_samples = static_cast<std::size_t>(std::llround(result.t_end_s / dt));
  if (o.keep_history) {
    // A row per sub-step of the record (more when the free motion follows): one allocation instead of a doubling
    // series. Under the sanitizers each allocation of this size is a fresh mmap whose pages fault one by one (issue 42:
    // the identification's thousands of analyses spent 40 % of their time in the kernel).
    result.history.reserve(1 + forced_samples * start.n_sub);
    if (observer) result.observer_history.reserve(forced_samples);
  }
  ResponseRecorder recorder(wall, o, result);
  recorder.row(0.0, to_double(ug0), to_double(vg0), engine);
  std::size_t k = 0;
  for (; k < forced_samples && !engine.stepper().collapsed(); ++k) {
    note_input(sample_or_zero(motion.ug_mps2, k + 1), sample_or_zero(motion.vg_mps2, k + 1));
    analysis_sample(engine, Engine::input(sample_or_zero(motion.ug_mps2, k + 1)),
                    Engine::input(sample_or_zero(motion.vg_mps2, k + 1)), double(k) * dt, dt, h, o, recorder, result,
                    observer);
  }
  result.collapsed = engine.stepper().collapsed();

  // After the record: free motion until the verdict says safe, or collapse.
  const auto free_samples = static_cast<std::size_t>(std::llround(o.free_motion_limit_s / dt));
  const typename Engine::Input zero = Engine::input(0.0);
  std::size_t free = 0;
  const bool until_rest = o.initial_x_m.has_value();  // a release test: the whole decay
  const auto decided = [&] { return until_rest ? !engine.stepper().moving() : engine.safe(); };
  for (; !engine.stepper().collapsed() && !decided() && free < free_samples; ++free, ++k) {
    note_input(0.0, 0.0);
    analysis_sample(engine, zero, zero, double(k) * dt, dt, h, o, recorder, result, observer);
  }
  result.t_final_s = double(k) * dt;
  if (!result.collapsed && engine.stepper().collapsed()) result.collapse_after_end = true;
  result.free_motion_undecided =
      !engine.stepper().collapsed() && free == free_samples && free_samples > 0 && !engine.safe();
  if (result.t_collapse_s) result.t_max_abs_x_s = *result.t_collapse_s;  // the maximum is the collapse point
  if (observer) observer->summarise(result.observer, result.n_impacts);
  if (measure) detail::measure_published(start.setup, o, dt, start.n_sub, fed, result.alarm);
  return result;
}

}  // namespace

namespace detail {

AnalysisStart start_analysis(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o,
                             AnalysisResult& result) {
  AnalysisStart start;
  start.n_sub = static_cast<std::size_t>(core::substeps_per_sample(motion.dt_s, o.max_step_s));
  start.h_s = motion.dt_s / double(start.n_sub);
  result.dt_s = start.h_s;
  result.sample_dt_s = motion.dt_s;
  result.duration_s = motion.duration_s();
  result.t_end_s = o.t_end_s ? *o.t_end_s : result.duration_s;
  result.pga_mps2 = peak_abs(motion.ug_mps2);
  result.r = core::restitution_energy_ratio(wall, o.restitution);
  core::StepperOptions so;
  so.dt_s = start.h_s;
  so.kappa = o.kappa;
  start.setup = core::make_stepper_setup(wall, o.model, result.r, so);
  result.x_inst_m = std::min(start.setup.x_inst_m[0], start.setup.x_inst_m[1]);
  result.threshold_mps2 = std::min(core::threshold_mps2(start.setup.model, Side::negative, wall.g_mps2),
                                   core::threshold_mps2(start.setup.model, Side::positive, wall.g_mps2));
  return start;
}

DoubleAnalysisEngine::DoubleAnalysisEngine(const core::WallParameters& wall, const core::StepperSetup<double>& setup,
                                           const AnalysisOptions& o, double dt_s, std::size_t n_sub) {
  chain_.init(setup, chain_alarm_settings(o), dt_s, static_cast<int>(n_sub));
  for (int i = 0; i < 2; ++i) {
    const Side side = i == 0 ? Side::negative : Side::positive;
    free_k_[i] = core::evaluate(setup.model, side, 0.0, wall.g_mps2);
    x_inst_m_[i] = setup.x_inst_m[i];
  }
  barrier_jpm_ = std::min(core::energy_barrier_jpm(setup.model, Side::negative, wall.g_mps2),
                          core::energy_barrier_jpm(setup.model, Side::positive, wall.g_mps2));
}

}  // namespace detail

AnalysisResult analyse(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o) {
  check_options(wall, motion, o);
  if (o.arithmetic == Arithmetic::fixed_point) return run_analysis<detail::FixedAnalysisEngine>(wall, motion, o);
  return run_analysis<detail::DoubleAnalysisEngine>(wall, motion, o);
}

}  // namespace rockwatch::sim
