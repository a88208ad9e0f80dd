// `rockwatch study --forecast` (issue 29 item 4): the ensemble forecast's scores (sim::study::forecast_outcome,
// sim/include/rockwatch/sim/study/forecast_scores.hpp: reliability, Brier, the leave-one-record-out baseline and
// recalibration, lead times) written as summary.json's "forecast", forecast.csv and the text report.
#pragma once

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/forecast_evaluation.hpp"
#include "rockwatch/sim/study/forecast_scores.hpp"

namespace rockwatch::cli {

// summary.json's "forecast": definitions, settings, held_out, counts, brier, reliability, calibration, baseline,
// lead {ensemble_5_percent, baseline_5_percent, imminent, ensemble_at_imminent_false_alarms,
// baseline_at_imminent_false_alarms}, goals.
nlohmann::ordered_json forecast_summary_json(const sim::study::ForecastEvaluationPlan& evaluation,
                                             const sim::study::ForecastOutcome& outcome);

// Everything that decides the evaluation's results (study.json's digest with --forecast).
nlohmann::ordered_json forecast_plan_json(const sim::study::ForecastEvaluationPlan& evaluation);

// forecast.csv: one row per forecast: run, record, component, r, pga_g, t_s, p_collapse, p_collapse_se,
// q50_max_x_over_x_inst, q90_max_x_over_x_inst, energy_ratio_max_2s, x_over_x_inst, imminent, outcome, baseline_p
// (leave one record out; empty without), collapsed, t_collapse_s, p_calibrated (leave one record out; empty without).
void write_forecast_csv(std::ostream& out, const sim::study::StudyPlan& plan,
                        const std::vector<sim::study::ForecastRunResult>& results, const sim::study::ForecastOutcome& outcome);

std::string forecast_summary_text(const sim::study::ForecastEvaluationPlan& evaluation,
                                  const sim::study::ForecastOutcome& outcome);

}  // namespace rockwatch::cli
