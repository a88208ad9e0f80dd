#include "rockwatch/sim/study/observer_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rockwatch/sim/synthesis/random_stream.hpp"
#include "rockwatch/sim/study/parallel_runs.hpp"

namespace rockwatch::sim::study {

namespace {

// RMS of a − truth over the rows of the common step grid where either moves (the grids are the same: same motion,
// same step; rows of a collapse point are skipped unless both have them).
std::optional<double> rms_x_error(const AnalysisResult& a, const AnalysisResult& truth) {
  double sum = 0.0;
  std::size_t n = 0;
  const std::size_t rows = std::min(a.history.size(), truth.history.size());
  for (std::size_t i = 0; i < rows; ++i) {
    const HistoryRow& x = a.history[i];
    const HistoryRow& t = truth.history[i];
    if (x.t_s != t.t_s) continue;
    if (x.x_m == 0.0 && t.x_m == 0.0) continue;
    const double e = x.x_m - t.x_m;
    sum += e * e;
    ++n;
  }
  if (n == 0) return std::nullopt;
  return std::sqrt(sum / double(n));
}

class Worker {
 public:
  Worker(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation, std::size_t longest, bool any_vertical)
      : plan_(plan), evaluation_(evaluation) {
    motion_.ug_mps2.reserve(longest);
    if (any_vertical) motion_.vg_mps2.reserve(longest);
  }

  ObserverRunResult run_one(std::size_t index) {
    const ObserverRunKey key = observer_run_key(plan_, evaluation_, index);
    const StudyRecord& rec = plan_.records[key.record_index];
    const double factor = plan_.pga_g[key.pga_index] * plan_.wall.g_mps2 / rec.peak_ug_mps2;
    const std::size_t n = rec.ug_mps2.size();
    motion_.dt_s = rec.dt_s;
    motion_.ug_mps2.resize(n);
    for (std::size_t i = 0; i < n; ++i) motion_.ug_mps2[i] = rec.ug_mps2[i] * factor;
    if (plan_.vertical[key.vertical_index]) {
      motion_.vg_mps2.resize(n);
      for (std::size_t i = 0; i < n; ++i) motion_.vg_mps2[i] = rec.vg_mps2[i] * factor;
    } else {
      motion_.vg_mps2.clear();
    }
    const MismatchCase& c = evaluation_.cases[key.case_index];

    ObserverRunResult out;
    out.done = true;
    try {
      // The truth: the true wall on the double engine, its history for the sensors and the x errors.
      AnalysisOptions t = plan_.analysis;
      t.arithmetic = Arithmetic::double_precision;
      t.restitution = c.restitution;
      t.keep_history = true;
      t.evaluate_alarm = false;
      t.max_impacts_kept = 0;
      t.max_alarm_transitions_kept = 0;
      t.mark_counted_impact = evaluation_.r_after_impacts + 1;
      const AnalysisResult truth = analyse(c.wall, motion_, t);
      out.true_collapsed = truth.verdict_collapse();
      out.true_t_collapse_s = truth.t_collapse_s;
      out.true_r = truth.r;
      out.true_x_inst_m = truth.x_inst_m;
      out.true_max_abs_x_m = truth.max_abs_x_m;
      out.true_impacts = truth.n_impacts;
      SensorModel sensors = evaluation_.sensors;
      if (c.accel_noise_mps2) sensors.a_noise_mps2 = c.accel_noise_mps2;
      std::uint64_t seed_state = evaluation_.sensors.seed ^ (0x9E3779B97F4A7C15ULL * (std::uint64_t(index) + 1));
      sensors.seed = synthesis::splitmix64(seed_state);
      const std::vector<core::WallSensorSample> samples = synthesize_wall_sensors(c.wall, truth, motion_.dt_s, sensors);

      // The nominal wall, open loop and fused, with the alarm.
      AnalysisOptions o = plan_.analysis;
      o.restitution = evaluation_.nominal_restitution;
      o.keep_history = true;
      o.evaluate_alarm = true;
      o.max_impacts_kept = 0;
      o.max_alarm_transitions_kept = 0;
      const AnalysisResult open = analyse(plan_.wall, motion_, o);
      out.open_collapsed = open.verdict_collapse();
      out.open_t_first_imminent_s = open.alarm.t_first_imminent_s;
      out.open_x_rms_error_m = rms_x_error(open, truth);
      o.wall_sensors = &samples;
      o.observer = evaluation_.observer;
      o.observer_r_after_impacts = evaluation_.r_after_impacts;
      o.observer_estimate_before_s = truth.t_counted_impact_s;
      const AnalysisResult fused = analyse(plan_.wall, motion_, o);
      out.fused_collapsed = fused.verdict_collapse();
      out.fused_t_first_imminent_s = fused.alarm.t_first_imminent_s;
      out.fused_x_rms_error_m = rms_x_error(fused, truth);
      out.r_estimate = fused.observer.r_estimate;
      out.r_estimate_after_impacts = fused.observer.r_estimate_after_impacts;
      out.x_inst_estimate_m = fused.observer.x_inst_estimate_m;
      out.x_inst_estimate_after_impacts_m = fused.observer.x_inst_estimate_after_impacts_m;
      out.r_estimate_after_true_impacts = fused.observer.r_estimate_before_time;
      out.x_inst_estimate_after_true_impacts_m = fused.observer.x_inst_estimate_before_time_m;
      out.fused_impacts = fused.n_impacts;
      out.bias_estimate_m = fused.observer.bias_estimate_m;
      out.n_updates = fused.observer.n_updates;
      out.n_rejected = fused.observer.n_rejected;
      out.n_reinitialised = fused.observer.counters.reinitialised;
      out.steps_sensor_lost = fused.observer.steps_sensor_lost;
    } catch (const AnalysisError& e) {
      out = ObserverRunResult{};
      out.done = true;
      out.error = e.what();
    }
    return out;
  }

 private:
  const StudyPlan& plan_;
  const ObserverEvaluationPlan& evaluation_;
  GroundMotion motion_;
};

}  // namespace

SensorModel study_sensor_model() {
  SensorModel m;
  m.x_noise_m = 0.5e-3;
  m.x_bias_m = 2e-3;
  return m;
}

std::vector<MismatchCase> standard_mismatch_cases(const core::WallParameters& nominal) {
  std::vector<MismatchCase> cases;
  core::Restitution ana, r08;
  ana.kind = core::RestitutionKind::ana;
  r08.kind = core::RestitutionKind::value;
  r08.value = 0.8;
  const core::Restitution exp{};
  cases.push_back(MismatchCase{"r_ana", "true r = r_ana, nominal r_exp = 0.9 r_ana", nominal, ana, std::nullopt});
  cases.push_back(MismatchCase{"r_0.8", "true r = 0.8, nominal r_exp = 0.9 r_ana", nominal, r08, std::nullopt});
  for (const double f : {0.85, 0.9, 1.1}) {
    core::WallParameters w = nominal;
    w.b_m = f * nominal.b_m;
    const std::string factor = f == 0.85 ? "0.85" : f == 0.9 ? "0.9" : "1.1";
    cases.push_back(MismatchCase{"b_" + factor, "true b = " + factor + " b (r_exp of the true wall)", w, exp,
                                 std::nullopt});
  }
  core::WallParameters split = nominal;
  const double h = nominal.h1_m + nominal.h2_m;
  split.h1_m = h * 1.5 / 3.5;
  split.h2_m = h * 2.0 / 3.5;
  cases.push_back(MismatchCase{"h1_h2_1.5_2.0", "true h1 : h2 = 1.5 : 2.0, same h (r_exp of the true wall)", split, exp,
                               std::nullopt});
  for (const double fp : {2000.0, 3000.0}) {
    core::WallParameters w = nominal;
    w.fp_npm = nominal.fp_npm + fp;
    const std::string kn = fp == 2000.0 ? "2" : "3";
    cases.push_back(MismatchCase{"fp_" + kn + "kN", "true overburden + " + kn + " kN/m (r_exp of the true wall)", w, exp,
                                 std::nullopt});
  }
  const std::size_t transducer_only = cases.size();
  for (std::size_t i = 0; i < transducer_only; ++i) {
    MismatchCase c = cases[i];
    c.name += "+accel";
    c.description += "; with the accelerometer (0.05 m/s2)";
    c.accel_noise_mps2 = 0.05;
    cases.push_back(c);
  }
  return cases;
}

std::size_t observer_run_count(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation) {
  return evaluation.cases.size() * plan.vertical.size() * plan.records.size() * plan.pga_g.size();
}

ObserverRunKey observer_run_key(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation, std::size_t index) {
  const std::size_t total = observer_run_count(plan, evaluation);
  if (index >= total) {
    throw AnalysisError("observer run index " + std::to_string(index) + " is out of range (the evaluation has " +
                        std::to_string(total) + " runs)");
  }
  ObserverRunKey key;
  key.pga_index = index % plan.pga_g.size();
  index /= plan.pga_g.size();
  key.record_index = index % plan.records.size();
  index /= plan.records.size();
  key.vertical_index = index % plan.vertical.size();
  key.case_index = index / plan.vertical.size();
  return key;
}

void run_observer_evaluation(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation,
                             std::vector<ObserverRunResult>& results, std::size_t jobs, const ProgressFn& progress,
                             const std::atomic<bool>* cancel) {
  validate_plan(plan);
  check_sensor_model(evaluation.sensors);
  if (evaluation.cases.empty()) throw AnalysisError("observer evaluation: no mismatch cases");
  for (const MismatchCase& c : evaluation.cases) {
    const core::WallCheck wc = core::validate_wall(c.wall);
    if (!wc.ok()) throw AnalysisError("mismatch case " + c.name + ": wall parameter " + wc.field + " " + wc.message);
  }
  const core::ObserverError err = core::validate_observer_options(evaluation.observer);
  if (err != core::ObserverError::ok) throw AnalysisError(core::observer_error_message(err));
  const std::size_t total = observer_run_count(plan, evaluation);
  if (results.empty()) results.resize(total);
  if (results.size() != total) {
    throw AnalysisError("observer results hold " + std::to_string(results.size()) + " runs, the evaluation has " +
                        std::to_string(total));
  }
  std::size_t longest = 0;
  for (const StudyRecord& r : plan.records) longest = std::max(longest, r.ug_mps2.size());
  const bool any_vertical = std::find(plan.vertical.begin(), plan.vertical.end(), true) != plan.vertical.end();
  run_pending(results, jobs, progress, cancel, [&] { return Worker(plan, evaluation, longest, any_vertical); });
}

}  // namespace rockwatch::sim::study
