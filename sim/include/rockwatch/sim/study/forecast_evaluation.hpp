// The ensemble forecast's evaluation (`rockwatch study --forecast`, issue 29 item 4): for each horizontal-only case
// (restitution, vertical = without) × record × PGA level of a study plan, one analysis (double engine, history kept,
// the alarm evaluated) and, every `every_s` seconds of it while the wall is not at rest, one forecast
// (sim::EnsembleForecaster, SPEC §10) from the run's own state, its ground model fitted to the record up to then.
// Each forecast is kept with what the scores need: P(collapse within H) and its standard error, the quantiles, the
// state-only baseline's two features (max E/E_barrier over the last 2 s and |x|/x_inst) and its outcome (the run
// collapsed in (t, t + H]). The scores themselves (reliability, Brier, baseline, lead times) are the caller's.
//
// The forecasts start from the model's own state (open loop, the nominal wall that made the outcome): the
// evaluation measures the ground model and the state spread, not the wall model's error.
//
// Run order (the run index), outermost first: restitution case, record, PGA level. Members' seeds are the settings'
// (common random numbers), so the results do not depend on the thread count.
#pragma once

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/sim/ensemble_forecast.hpp"
#include "rockwatch/sim/study/batch_study.hpp"

namespace rockwatch::sim::study {

// The baseline's energy feature: the largest E/E_barrier over this window ending at the forecast time [s].
inline constexpr double kForecastEnergyWindow_s = 2.0;
// Range of the forecast interval.
inline constexpr double kForecastEveryMin_s = 0.01, kForecastEveryMax_s = 60.0;

struct ForecastEvaluationPlan {
  ForecastSettings settings;  // members, horizon, seed (the rest: the forecaster's defaults, SPEC §10)
  double every_s = 0.1;       // one forecast every this many seconds of a run [s]
};

struct ForecastPoint {
  double t_s = 0.0;                    // forecast time [s]
  double p_collapse = 0.0;             // P(collapse within H)
  double p_collapse_se = 0.0;          // its Monte-Carlo standard error
  double q50_max_x_over_x_inst = 0.0;  // quantiles of max |x|/x_inst over the horizon
  double q90_max_x_over_x_inst = 0.0;
  double energy_ratio_max = 0.0;       // max E/E_barrier over [t − 2 s, t] (the run's own state, its side) [-]
  double x_over_x_inst = 0.0;          // |x|/x_inst at t (x_inst of the side) [-]
  bool imminent = false;               // the run's alarm reached IMMINENT at or before t
  bool outcome = false;                // the run collapsed in (t, t + H]
};

struct ForecastRunResult {
  bool done = false;
  std::string error;                          // the analysis refused the input: no forecasts
  bool collapsed = false;                     // verdict_collapse() of the double engine
  std::optional<double> t_collapse_s;
  std::optional<double> t_first_imminent_s;   // the alarm's first IMMINENT
  std::size_t at_rest = 0;                    // forecast times skipped: the wall was at rest
  std::vector<ForecastPoint> points;
};

struct ForecastRunKey {
  std::size_t restitution_index = 0, record_index = 0, pga_index = 0;
};

std::size_t forecast_run_count(const StudyPlan& plan);
ForecastRunKey forecast_run_key(const StudyPlan& plan, std::size_t index);

// Throws AnalysisError naming the setting for an evaluation plan out of range (forecast settings, every_s).
void validate_forecast_evaluation(const ForecastEvaluationPlan& evaluation);

// Runs every run not done (results resized to forecast_run_count if empty), on `jobs` threads (0: all), the plan
// validated as run_study does; the alarm is the plan's (its defaults when the plan does not evaluate it). Stops early
// when *cancel becomes true. Throws AnalysisError for an inconsistent plan or evaluation.
void run_forecast_evaluation(const StudyPlan& plan, const ForecastEvaluationPlan& evaluation,
                             std::vector<ForecastRunResult>& results, std::size_t jobs,
                             const ProgressFn& progress = {}, const std::atomic<bool>* cancel = nullptr);

}  // namespace rockwatch::sim::study
