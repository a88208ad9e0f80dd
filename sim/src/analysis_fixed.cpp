#include "analysis_fixed.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rockwatch/core/fixed_instability_indicators.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"

namespace rockwatch::sim::detail {

using core::AccelQ7_56;
using core::Side;

namespace {

// The record on the integration grid (GridInput), converted to the engine's input format once per step.
struct FixedGridInput {
  GridInput grid;
  AccelQ7_56 ug(std::size_t k) const { return AccelQ7_56(grid.ug(k)); }
  AccelQ7_56 vg(std::size_t k) const { return AccelQ7_56(grid.vg(k)); }
};

// Inputs beyond ±80 m/s² would saturate ẍ the engine's coefficients (docs/FIXED_POINT.md): refuse, naming the sample.
void check_input_range(const GroundMotion& motion) {
  constexpr double limit = 80.0;
  const std::vector<double>* series[2] = {&motion.ug_mps2, &motion.vg_mps2};
  const char* names[2] = {"horizontal", "vertical"};
  for (int c = 0; c < 2; ++c) {
    for (std::size_t i = 0; i < series[c]->size(); ++i) {
      if (std::fabs((*series[c])[i]) >= limit) {
        std::ostringstream m;
        m << names[c] << " sample " << i << " (t = " << double(i) * motion.dt_s << " s) is " << (*series[c])[i]
          << " m/s2: the fixed-point engine accepts |acceleration| < " << limit << " m/s2";
        throw AnalysisError(m.str());
      }
    }
  }
}

double fraction(core::FractionQ1_62 f) { return f.to_double(); }

}  // namespace

void record_alarm_update(AlarmSummary& summary, std::size_t keep, double t_s, const core::AlarmUpdate& u,
                         const AlarmSample& sample) {
  if (u.level > summary.max_level) summary.max_level = u.level;
  if (u.level >= core::AlarmLevel::warning && !summary.t_first_warning_s) summary.t_first_warning_s = t_s;
  if (u.level >= core::AlarmLevel::imminent && !summary.t_first_imminent_s) summary.t_first_imminent_s = t_s;
  if (u.level >= core::AlarmLevel::collapsed && !summary.t_first_collapsed_s) summary.t_first_collapsed_s = t_s;
  if (!u.changed) return;
  ++summary.n_transitions;
  if (summary.transitions.size() >= keep) return;
  AlarmTransition t;
  t.t_s = t_s;
  t.level = u.level;
  t.previous = u.previous;
  t.reasons = u.reasons;
  t.x_m = sample.x_m;
  t.xd_mps = sample.xd_mps;
  t.t_to_instability_s = sample.t_to_instability_s;
  t.energy_ratio = sample.energy_ratio;
  summary.transitions.push_back(t);
}

AnalysisResult analyse_fixed(const core::WallParameters& wall, const GroundMotion& motion, const AnalysisOptions& o) {
  if (o.model != core::ModelKind::linear) throw AnalysisError("fixed-point arithmetic supports the linear model only");
  check_input_range(motion);

  AnalysisResult result;
  result.arithmetic = Arithmetic::fixed_point;
  const AnalysisStart start = start_analysis(wall, motion, o, result);
  const double h = start.h_s;
  const core::StepperSetup<double>& setup = start.setup;

  core::FixedRockingStepper stepper;
  const core::FixedSetupError error = stepper.init(setup);
  if (error != core::FixedSetupError::ok) throw AnalysisError(core::fixed_setup_error_message(error));

  core::FixedInstabilityConstants constants{};
  if (!core::make_fixed_instability_constants(setup, o.alarm, constants)) {
    throw AnalysisError("x_inst must be in (0.008, 1.9) m for the fixed-point instability indicators");
  }
  core::InstabilityAlarm alarm;
  alarm.init(core::hold_samples(o.alarm, h));
  if (o.evaluate_alarm) result.alarm.evaluated = true;

  const FixedGridInput input{GridInput{motion, start.n_sub}};
  stepper.reset(input.ug(0), input.vg(0));

  auto record_row = [&](double t_s, AccelQ7_56 ug, AccelQ7_56 vg) {
    const double x = stepper.x_m().to_double();
    const double ax = std::fabs(x);
    if (ax > result.max_abs_x_m) {
      result.max_abs_x_m = ax;
      result.t_max_abs_x_s = t_s;
    }
    if (o.keep_history) {
      result.history.push_back(HistoryRow{t_s, ug.to_double(), vg.to_double(), x, stepper.xd_mps().to_double(),
                                          stepper.xdd_mps2().to_double(), -x / wall.h1_m, x / wall.h2_m,
                                          stepper.side() == Side::positive ? 1 : -1});
    }
  };
  auto record_events = [&](double t0_s, const core::FixedStepReport& rep) {
    if (rep.saturated) result.saturated = true;
    if (rep.started && !result.t_first_motion_s) result.t_first_motion_s = t0_s + fraction(rep.start_fraction) * h;
    if (rep.impacts_total > 0 && result.impacts.size() < o.max_impacts_kept) {
      result.impacts.push_back(ImpactEvent{t0_s + fraction(rep.first_impact_fraction) * h,
                                           rep.first_impact_v_before_mps.to_double(),
                                           rep.first_impact_v_after_mps.to_double()});
    }
    result.n_impacts += rep.impacts_counted;
    result.n_impacts_total += rep.impacts_total;
    if (rep.exceeded && !result.t_exceed_s) result.t_exceed_s = t0_s + fraction(rep.exceed_fraction) * h;
    if (rep.collapsed) {
      result.t_collapse_s = t0_s + fraction(rep.collapse_fraction) * h;
      return *result.t_collapse_s;
    }
    return t0_s + h;
  };
  record_row(0.0, input.ug(0), input.vg(0));
  // The indicators also decide the post-record verdict, so they run whether or not the alarm is reported.
  core::FixedInstabilityIndicators indicators{};
  auto after_step = [&](double t_s, const core::FixedStepReport& rep) {
    indicators = core::evaluate_instability(constants, stepper, rep);
    if (!o.evaluate_alarm) return;
    const core::AlarmUpdate u = alarm.update(indicators.conditions);
    AlarmSample sample;
    sample.x_m = stepper.x_m().to_double();
    sample.xd_mps = stepper.xd_mps().to_double();
    if (indicators.t_valid) sample.t_to_instability_s = indicators.t_to_instability_s.to_double();
    sample.energy_ratio = indicators.energy_ratio.to_double();
    record_alarm_update(result.alarm, o.max_alarm_transitions_kept, t_s, u, sample);
  };

  const auto forced_steps = static_cast<std::size_t>(std::llround(result.t_end_s / h));
  std::size_t k = 0;
  for (; k < forced_steps && !stepper.collapsed(); ++k) {
    const AccelQ7_56 ug = input.ug(k + 1), vg = input.vg(k + 1);
    const core::FixedStepReport rep = stepper.step(ug, vg);
    const double t_s = record_events(double(k) * h, rep);
    record_row(t_s, ug, vg);
    after_step(t_s, rep);
  }
  result.collapsed = stepper.collapsed();

  // After the record: free motion until safe (|x| < x_inst and E < E_barrier, SPEC §4.3) or collapse, decided in
  // fixed point by the indicators (ρ = E/E_barrier).
  const auto free_steps = static_cast<std::size_t>(std::llround(o.free_motion_limit_s / h));
  auto safe = [&]() {
    if (!stepper.moving()) return true;
    return !indicators.conditions.over_instability_displacement && indicators.energy_ratio < core::RatioQ7_24(1);
  };
  std::size_t free = 0;
  const AccelQ7_56 zero{};
  for (; !stepper.collapsed() && !safe() && free < free_steps; ++free, ++k) {
    const core::FixedStepReport rep = stepper.step(zero, zero);
    const double t_s = record_events(double(k) * h, rep);
    record_row(t_s, zero, zero);
    after_step(t_s, rep);
  }
  result.t_final_s = double(k) * h;
  if (!result.collapsed && stepper.collapsed()) result.collapse_after_end = true;
  result.free_motion_undecided = !stepper.collapsed() && free == free_steps && free_steps > 0 && !safe();
  if (result.t_collapse_s) result.t_max_abs_x_s = *result.t_collapse_s;
  return result;
}

}  // namespace rockwatch::sim::detail
