// `rockwatch study --alarms --observer`: the wall observer's evaluation (sim::study::run_observer_evaluation), its
// plan for the study's wall, and its scores (sim::study::observer_outcome) written as summary.json's "observer",
// observer_runs.csv and the text report.
#pragma once

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/observer_evaluation.hpp"
#include "rockwatch/sim/study/observer_scores.hpp"

namespace rockwatch::cli {

// The evaluation of `rockwatch study --observer`: the standard mismatch cases for the study's wall, nominal r_exp,
// the study's sensors (0.5 mm noise, 2 mm offset), the given observer settings.
sim::study::ObserverEvaluationPlan observer_evaluation_plan(const sim::study::StudyPlan& plan,
                                                            const core::ObserverOptions& observer);

// Everything that decides the evaluation's results: nominal restitution, cases (walls, restitutions), sensors,
// observer settings, r_after_impacts. Part of the plan description (study.json's digest) with --observer.
nlohmann::ordered_json observer_plan_json(const sim::study::ObserverEvaluationPlan& evaluation);

// summary.json's "observer": definitions, settings, runs, open_loop and fused {recall, false_alarm_rate,
// lead_time_s_median, lead_time_s_p05, lead_time_s_min, counts}, estimation {x_rms_over_x_inst {fused, open_loop},
// r_error_after_impacts, r_error_final}, per_case [...].
nlohmann::ordered_json observer_summary_json(const sim::study::ObserverEvaluationPlan& evaluation,
                                             const sim::study::ObserverOutcome& outcome);

// observer_runs.csv: one row per evaluation run: case, record, component, vertical, pga_g, true_collapsed,
// true_t_collapse_s, true_r, true_x_inst_m, true_max_abs_x_m, true_impacts, open_collapsed,
// open_t_first_imminent_s, fused_collapsed, fused_t_first_imminent_s, open_x_rms_error_m, fused_x_rms_error_m,
// r_estimate, r_estimate_after_impacts, fused_impacts, bias_estimate_m, n_updates, n_rejected, n_reinitialised,
// steps_sensor_lost, run, error (empty fields where a value did not happen).
void write_observer_runs_csv(std::ostream& out, const sim::study::StudyPlan& plan,
                             const sim::study::ObserverEvaluationPlan& evaluation,
                             const std::vector<sim::study::ObserverRunResult>& results);

// The lines of the text report.
std::string observer_summary_text(const sim::study::ObserverEvaluationPlan& evaluation, const sim::study::ObserverOutcome& outcome);

}  // namespace rockwatch::cli
