#include "rockwatch/sim/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analysis_fixed.hpp"
#include "rockwatch/core/instability_indicators.hpp"
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

// Each setting on its own, so the message names the one at fault (core::alarm_settings_valid is their conjunction).
void check_alarm_settings(const core::AlarmSettings& a) {
  if (!(a.lambda_warning > 0.0 && a.lambda_warning <= 1.0)) {
    throw AnalysisError("alarm lambda_warning must be in (0, 1] (got " + number_text(a.lambda_warning) + ")");
  }
  if (!(a.hold_s >= 0.0 && a.hold_s <= 3600.0)) {
    throw AnalysisError("alarm hold_s must be in [0, 3600] s (got " + number_text(a.hold_s) + ")");
  }
  if (!(a.energy_margin >= 1.0 && a.energy_margin <= 100.0)) {
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
  if (o.t_end_s && !(std::isfinite(*o.t_end_s) && *o.t_end_s >= 0.0)) throw AnalysisError("t_end must be >= 0 s");
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
  if (o.arithmetic == Arithmetic::fixed_point && o.model != core::ModelKind::linear) {
    throw AnalysisError("fixed-point arithmetic supports the linear model only");
  }
}

// Collects the summary from the stepper's per-step reports.
class ResponseRecorder {
 public:
  ResponseRecorder(const core::WallParameters& wall, const AnalysisOptions& o, AnalysisResult& r)
      : wall_(wall), options_(o), result_(r) {}

  void row(double t_s, double ug, double vg, const core::RockingStepper<double>& s) {
    const auto& st = s.state();
    const double ax = std::fabs(st.x_m);
    if (ax > result_.max_abs_x_m) {
      result_.max_abs_x_m = ax;
      result_.t_max_abs_x_s = t_s;
    }
    if (options_.keep_history) {
      result_.history.push_back(HistoryRow{t_s, ug, vg, st.x_m, st.xd_mps, st.xdd_mps2, -st.x_m / wall_.h1_m,
                                           st.x_m / wall_.h2_m, s.side() == Side::positive ? 1 : -1});
    }
  }

  // Returns the time the state now stands at: the step end, or the collapse point.
  double events(double t0_s, double h_s, const core::StepReport<double>& rep) {
    if (rep.started && !result_.t_first_motion_s) result_.t_first_motion_s = t0_s + rep.start_fraction * h_s;
    if (rep.impacts_total > 0 && result_.impacts.size() < options_.max_impacts_kept) {
      result_.impacts.push_back(ImpactEvent{t0_s + rep.first_impact_fraction * h_s, rep.first_impact_v_before_mps,
                                            rep.first_impact_v_after_mps});
    }
    result_.n_impacts += rep.impacts_counted;
    result_.n_impacts_total += rep.impacts_total;
    if (rep.exceeded && !result_.t_exceed_s) result_.t_exceed_s = t0_s + rep.exceed_fraction * h_s;
    if (rep.collapsed) {
      result_.t_collapse_s = t0_s + rep.collapse_fraction * h_s;
      return *result_.t_collapse_s;
    }
    return t0_s + h_s;
  }

 private:
  const core::WallParameters& wall_;
  const AnalysisOptions& options_;
  AnalysisResult& result_;
};

// Runs the instability alarm on the stepper's state after each integration step and keeps its summary
// (AnalysisResult::alarm). Allocates only when a transition is kept (max_alarm_transitions_kept > 0).
class AlarmRecorder {
 public:
  AlarmRecorder(const core::StepperSetup<double>& setup, double h_s, const AnalysisOptions& o, AlarmSummary& summary)
      : enabled_(o.evaluate_alarm), keep_(o.max_alarm_transitions_kept), summary_(summary) {
    if (!enabled_) return;
    constants_ = core::make_instability_constants(setup, o.alarm);
    alarm_.init(core::hold_samples(o.alarm, h_s));
    summary_.evaluated = true;
  }

  // After a step: `t_s` is where the state stands (the step end, or the collapse point).
  void step(double t_s, const core::RockingStepper<double>& stepper, const core::StepReport<double>& rep) {
    if (!enabled_) return;
    const core::InstabilityIndicators<double> ind = core::evaluate_instability(constants_, stepper, rep);
    const core::AlarmUpdate u = alarm_.update(ind.conditions);
    detail::AlarmSample sample;
    sample.x_m = stepper.state().x_m;
    sample.xd_mps = stepper.state().xd_mps;
    if (ind.t_valid) sample.t_to_instability_s = ind.t_to_instability_s;
    sample.energy_ratio = ind.energy_ratio;
    detail::record_alarm_update(summary_, keep_, t_s, u, sample);
  }

 private:
  bool enabled_;
  std::size_t keep_;
  AlarmSummary& summary_;
  core::InstabilityConstants<double> constants_{};
  core::InstabilityAlarm alarm_;
};

}  // namespace

namespace detail {

AnalysisStart start_analysis(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o,
                             AnalysisResult& result) {
  AnalysisStart start;
  start.n_sub = static_cast<std::size_t>(std::max(1.0, std::ceil(motion.dt_s / o.max_step_s - 1e-9)));
  start.h_s = motion.dt_s / double(start.n_sub);
  result.dt_s = start.h_s;
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

}  // namespace detail

AnalysisResult analyse(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o) {
  check_options(wall, motion, o);
  if (o.arithmetic == Arithmetic::fixed_point) return detail::analyse_fixed(wall, motion, o);

  AnalysisResult result;
  result.arithmetic = Arithmetic::double_precision;
  const detail::AnalysisStart start = detail::start_analysis(wall, motion, o, result);
  const double h = start.h_s;
  const core::StepperSetup<double>& setup = start.setup;

  const detail::GridInput input{motion, start.n_sub};
  core::RockingStepper<double> stepper;
  stepper.init(setup);
  stepper.reset(input.ug(0), input.vg(0));
  ResponseRecorder recorder(wall, o, result);
  recorder.row(0.0, input.ug(0), input.vg(0), stepper);
  AlarmRecorder alarm(setup, h, o, result.alarm);

  const auto forced_steps = static_cast<std::size_t>(std::llround(result.t_end_s / h));
  std::size_t k = 0;
  for (; k < forced_steps && !stepper.collapsed(); ++k) {
    const double ug = input.ug(k + 1), vg = input.vg(k + 1);
    const core::StepReport<double> rep = stepper.step(ug, vg);
    const double t_s = recorder.events(double(k) * h, h, rep);
    recorder.row(t_s, ug, vg, stepper);
    alarm.step(t_s, stepper, rep);
  }
  result.collapsed = stepper.collapsed();

  // After the record: free motion until the energy says safe, or collapse (SPEC §4.3).
  const core::Coefficients<double> free_k[2] = {core::evaluate(setup.model, Side::negative, 0.0, wall.g_mps2),
                                                core::evaluate(setup.model, Side::positive, 0.0, wall.g_mps2)};
  const double barrier = std::min(core::energy_barrier_jpm(setup.model, Side::negative, wall.g_mps2),
                                  core::energy_barrier_jpm(setup.model, Side::positive, wall.g_mps2));
  auto safe = [&]() {
    if (!stepper.moving()) return true;
    const auto& st = stepper.state();
    const int i = core::side_index(stepper.side());
    const double energy = core::mechanical_energy(free_k[i], st.x_m, st.xd_mps);
    return std::fabs(st.x_m) < setup.x_inst_m[i] && energy < barrier;
  };
  const auto free_steps = static_cast<std::size_t>(std::llround(o.free_motion_limit_s / h));
  std::size_t free = 0;
  for (; !stepper.collapsed() && !safe() && free < free_steps; ++free, ++k) {
    const core::StepReport<double> rep = stepper.step(0.0, 0.0);
    const double t_s = recorder.events(double(k) * h, h, rep);
    recorder.row(t_s, 0.0, 0.0, stepper);
    alarm.step(t_s, stepper, rep);
  }
  result.t_final_s = double(k) * h;
  if (!result.collapsed && stepper.collapsed()) result.collapse_after_end = true;
  result.free_motion_undecided = !stepper.collapsed() && free == free_steps && free_steps > 0 && !safe();
  if (result.t_collapse_s) result.t_max_abs_x_s = *result.t_collapse_s;  // the maximum is the collapse point
  return result;
}

}  // namespace rockwatch::sim
