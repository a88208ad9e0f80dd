// `rockwatch study --alarms --observer`: the wall observer's evaluation (sim::study::run_observer_evaluation) scored
// against the TRUE wall's verdict with the study's own alarm scores (alarm_outcome: recall, false alarms, lead times),
// for the nominal wall open loop and fused, plus the estimation errors: x RMS error over x_inst (fused and open loop
// against the true trajectory) and |r̂ − r_true| after n impacts; over all runs and per mismatch case.
#pragma once

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/observer_evaluation.hpp"
#include "study/statistics/study_summary.hpp"

namespace rockwatch::cli {

// Median, 95th percentile (type 7) and maximum of a set of values; none when empty.
struct Spread {
  std::size_t n = 0;
  std::optional<double> median, p95, max;
};

struct ObserverScore {
  std::size_t runs = 0;              // runs with results (no error)
  std::size_t runs_with_error = 0;
  AlarmOutcome open_loop, fused;     // against the true wall's verdict
  Spread fused_x_rms_over_x_inst;    // per run, over the rows where the true or the fused wall moves
  Spread open_x_rms_over_x_inst;
  std::size_t fused_x_within_2_percent = 0;
  Spread r_error_after_impacts;      // |r̂ − r_true| after n impacts, over the runs with at least n
  Spread r_error_final;              // |r̂ − r_true| at the end, over the same runs
  std::size_t r_within_0_02 = 0;     // of them, after n impacts
  Spread x_inst_error_after_impacts;  // |x̂_inst − x_inst,true| / x_inst,true after n impacts, same runs
  std::size_t x_inst_within_3_percent = 0;  // of them
  // The same after n counted impacts of the TRUE wall (issue 27's "once the wall has impacted 5 times"), over the runs
  // whose true wall impacted more than n times: the fused wall's own first impacts can be noise-driven chatter of the
  // model while the real wall is still at rest.
  Spread r_error_after_true_impacts, x_inst_error_after_true_impacts;
  std::size_t r_within_0_02_after_true_impacts = 0, x_inst_within_3_percent_after_true_impacts = 0;
  std::size_t runs_reinitialised = 0, runs_sensor_lost = 0;
};

struct ObserverOutcome {
  ObserverScore all;
  std::vector<ObserverScore> per_case;  // in the evaluation's case order
};

// The evaluation of `rockwatch study --observer`: the standard mismatch cases for the study's wall, nominal r_exp,
// the study's sensors (0.5 mm noise, 2 mm offset), the given observer settings.
sim::study::ObserverEvaluationPlan observer_evaluation_plan(const sim::study::StudyPlan& plan,
                                                            const core::ObserverOptions& observer);

// Everything that decides the evaluation's results: nominal restitution, cases (walls, restitutions), sensors,
// observer settings, r_after_impacts. Part of the plan description (study.json's digest) with --observer.
nlohmann::ordered_json observer_plan_json(const sim::study::ObserverEvaluationPlan& evaluation);

ObserverOutcome observer_outcome(const sim::study::StudyPlan& plan,
                                 const sim::study::ObserverEvaluationPlan& evaluation,
                                 const std::vector<sim::study::ObserverRunResult>& results);

// summary.json's "observer": definitions, settings, runs, open_loop and fused {recall, false_alarm_rate,
// lead_time_s_median, lead_time_s_p05, lead_time_s_min, counts}, estimation {x_rms_over_x_inst {fused, open_loop},
// r_error_after_impacts, r_error_final}, per_case [...].
nlohmann::ordered_json observer_summary_json(const sim::study::ObserverEvaluationPlan& evaluation,
                                             const ObserverOutcome& outcome);

// observer_runs.csv: one row per evaluation run: case, record, component, vertical, pga_g, true_collapsed,
// true_t_collapse_s, true_r, true_x_inst_m, true_max_abs_x_m, true_impacts, open_collapsed,
// open_t_first_imminent_s, fused_collapsed, fused_t_first_imminent_s, open_x_rms_error_m, fused_x_rms_error_m,
// r_estimate, r_estimate_after_impacts, fused_impacts, bias_estimate_m, n_updates, n_rejected, n_reinitialised,
// steps_sensor_lost, run, error (empty fields where a value did not happen).
void write_observer_runs_csv(std::ostream& out, const sim::study::StudyPlan& plan,
                             const sim::study::ObserverEvaluationPlan& evaluation,
                             const std::vector<sim::study::ObserverRunResult>& results);

// The lines of the text report.
std::string observer_summary_text(const sim::study::ObserverEvaluationPlan& evaluation, const ObserverOutcome& outcome);

}  // namespace rockwatch::cli
