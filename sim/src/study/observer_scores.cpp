#include "rockwatch/sim/study/observer_scores.hpp"

#include <cmath>
#include <optional>

namespace rockwatch::sim::study {

namespace {

// The run as the study's alarm scores take it: the TRUE wall's verdict and collapse time, a nominal run's first
// IMMINENT.
AlarmRun as_alarm_run(const ObserverRunResult& r, const std::optional<double>& t_first_imminent_s) {
  return AlarmRun{r.true_collapsed, r.true_t_collapse_s, t_first_imminent_s};
}

ObserverScore score(const std::vector<const ObserverRunResult*>& runs, int r_after_impacts) {
  ObserverScore s;
  std::vector<AlarmRun> open, fused;
  std::vector<double> fused_x, open_x, r_after, r_final, x_inst_after, r_after_true, x_inst_after_true;
  for (const ObserverRunResult* r : runs) {
    if (!r->error.empty()) {
      ++s.runs_with_error;
      continue;
    }
    ++s.runs;
    open.push_back(as_alarm_run(*r, r->open_t_first_imminent_s));
    fused.push_back(as_alarm_run(*r, r->fused_t_first_imminent_s));
    if (r->fused_x_rms_error_m) {
      const double ratio = *r->fused_x_rms_error_m / r->true_x_inst_m;
      fused_x.push_back(ratio);
      if (ratio <= 0.02) ++s.fused_x_within_2_percent;
    }
    if (r->open_x_rms_error_m) open_x.push_back(*r->open_x_rms_error_m / r->true_x_inst_m);
    if (r->r_estimate_after_impacts && r->fused_impacts >= r_after_impacts) {
      const double e = std::fabs(*r->r_estimate_after_impacts - r->true_r);
      r_after.push_back(e);
      r_final.push_back(std::fabs(r->r_estimate - r->true_r));
      if (e <= 0.02) ++s.r_within_0_02;
      if (r->x_inst_estimate_after_impacts_m && r->true_x_inst_m > 0.0) {
        const double ex = std::fabs(*r->x_inst_estimate_after_impacts_m - r->true_x_inst_m) / r->true_x_inst_m;
        x_inst_after.push_back(ex);
        if (ex <= 0.03) ++s.x_inst_within_3_percent;
      }
    }
    if (r->r_estimate_after_true_impacts && r->x_inst_estimate_after_true_impacts_m && r->true_x_inst_m > 0.0) {
      const double e = std::fabs(*r->r_estimate_after_true_impacts - r->true_r);
      const double ex = std::fabs(*r->x_inst_estimate_after_true_impacts_m - r->true_x_inst_m) / r->true_x_inst_m;
      r_after_true.push_back(e);
      x_inst_after_true.push_back(ex);
      if (e <= 0.02) ++s.r_within_0_02_after_true_impacts;
      if (ex <= 0.03) ++s.x_inst_within_3_percent_after_true_impacts;
    }
    if (r->n_reinitialised > 0) ++s.runs_reinitialised;
    if (r->steps_sensor_lost > 0) ++s.runs_sensor_lost;
  }
  s.open_loop = alarm_outcome(open);
  s.fused = alarm_outcome(fused);
  s.fused_x_rms_over_x_inst = spread_of(fused_x);
  s.open_x_rms_over_x_inst = spread_of(open_x);
  s.r_error_after_impacts = spread_of(r_after);
  s.r_error_final = spread_of(r_final);
  s.x_inst_error_after_impacts = spread_of(x_inst_after);
  s.r_error_after_true_impacts = spread_of(r_after_true);
  s.x_inst_error_after_true_impacts = spread_of(x_inst_after_true);
  return s;
}

}  // namespace

ObserverOutcome observer_outcome(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation,
                                 const std::vector<ObserverRunResult>& results) {
  ObserverOutcome o;
  std::vector<const ObserverRunResult*> all;
  std::vector<std::vector<const ObserverRunResult*>> per_case(evaluation.cases.size());
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (!results[i].done) continue;
    all.push_back(&results[i]);
    per_case[observer_run_key(plan, evaluation, i).case_index].push_back(&results[i]);
  }
  o.all = score(all, evaluation.r_after_impacts);
  for (const auto& runs : per_case) o.per_case.push_back(score(runs, evaluation.r_after_impacts));
  return o;
}

}  // namespace rockwatch::sim::study
