// Is the ensemble forecast right? The forecasts of run_forecast_evaluation (`rockwatch study --forecast`, issue 29
// item 4) scored against what their runs did, every fitted figure chosen without the record it is applied to (leave
// one record out: the records of the other groups fit it; a group is the record's name, so a suite set's X and Y, the
// same earthquake, are left out together):
//   reliability   10 bins of P; observed frequency against the mean forecast; calibrated when |observed − mean P|
//                 ≤ 0.1 in every bin holding ≥ 30 forecasts;
//   Brier         mean (P − outcome)²; skill 1 − Brier/Brier(base rate), the base rate the sample's;
//   baseline      a logistic regression (fit_logistic) on (max E/E_barrier over the last 2 s, |x|/x_inst), fitted
//                 leave one record out on the same forecasts (its in-sample skill beside, for reference);
//   lead          a threshold p* chosen (leave one record out) so that at most 5 % of the other records' surviving
//                 runs ever reach it; then, on the record left out: survivors that reach it (false alarms),
//                 collapses that reach it before they collapse and how long before (lead); also p* chosen at the
//                 IMMINENT alarm's false-alarm rate on the other records; against IMMINENT's own lead and false
//                 alarms (no fitted parameter).
// The ensemble itself is fitted to nothing here; its defaults were chosen on sets 1-3 of the shipped suite (SPEC
// §10): study --sets 4-11 keeps them apart too. The CLI (host_tools/rockwatch/study/report/study_forecast.*)
// writes these figures as summary.json's "forecast", forecast.csv and the text report.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/forecast_evaluation.hpp"

namespace rockwatch::sim::study {

inline constexpr double kCalibrationTolerance = 0.1;       // |observed − mean P| in a bin
inline constexpr std::size_t kCalibrationMinForecasts = 30;  // bins with fewer are not judged
inline constexpr double kLeadFalseAlarmFraction = 0.05;    // p*: at most this fraction of survivors ever reach it

struct ReliabilityBin {
  double lo = 0.0, hi = 0.0;     // [lo, hi), the last bin closed
  std::size_t n = 0;
  double mean_p = 0.0, observed = 0.0;
};

// A warning rule (P ≥ p*, or IMMINENT) scored on runs: the rule's false alarms and leads.
struct LeadScore {
  std::size_t survivors = 0, survivors_flagged = 0;
  std::size_t collapsed = 0, collapsed_flagged = 0;  // flagged strictly before t_collapse
  std::optional<double> false_alarm_rate, recall;
  std::optional<double> lead_time_s_median, lead_time_s_p05;  // over the collapses flagged in time
  // Over every collapse, one missed counting 0 s: a rule that flags few collapses early cannot look better than one
  // that flags them all (the goal is judged on this).
  std::optional<double> lead_time_s_median_all_collapses;
  std::vector<double> lead_times_s;                  // ascending
  std::optional<double> p_star_min, p_star_median, p_star_max;  // over the folds (null for IMMINENT)
  std::size_t folds_without_threshold = 0;           // folds where no p* ≤ 1 met the limit: nothing flagged
};

// The ensemble's P recalibrated (SPEC §10 "Calibrated P", sim::ForecastCalibration): a logistic regression
// (fit_logistic_regression) on (1, logit of the clamped P, max E/E_barrier over 2 s, |x|/x_inst, logit × min(max E/E_barrier, 2)), fitted
// leave one record out (the folds of the baseline), scored as the raw P is.
struct CalibratedForecast {
  bool fitted = false;                               // two or more record groups
  std::vector<double> p;                             // per forecast, in the order of forecast.csv
  std::optional<double> brier, brier_skill, skill_vs_baseline;
  std::vector<ReliabilityBin> bins;
  std::size_t bins_judged = 0;
  std::optional<double> calibration_max_error;
  bool calibrated = false;
  LeadScore at_5, at_imminent;
  // Fitted on every record (in sample): what `rockwatch-monitor` and `simulate` would ship for this horizon.
  // c0, c_logit_p, c_energy_ratio_max_2s, c_x_over_x_inst, c_logit_p_x_energy_ratio_max_2s_capped
  std::vector<double> coefficients_all_records;
  std::optional<double> brier_skill_in_sample;
  // Per fold: the records whose forecasts fitted its coefficients never include the record it is applied to.
  std::size_t folds = 0, fold_rows_checked = 0;
};

struct ForecastOutcome {
  std::size_t runs = 0, runs_with_error = 0, collapsing_runs = 0, surviving_runs = 0;
  std::size_t forecasts = 0, at_rest_skipped = 0, groups = 0;
  std::optional<double> base_rate, brier, brier_base_rate, brier_skill;
  std::vector<ReliabilityBin> bins;
  std::size_t bins_judged = 0;
  std::optional<double> calibration_max_error;       // over the judged bins
  bool calibrated = false;
  // The state-only baseline, leave one record out (none with fewer than two groups).
  std::vector<double> baseline_p;                    // per forecast, in the order of forecast.csv
  std::optional<double> baseline_brier, baseline_skill, baseline_skill_in_sample;
  std::vector<double> baseline_weights_in_sample;    // const, energy_ratio_max, x_over_x_inst
  std::optional<double> skill_vs_baseline;           // 1 − Brier / Brier(baseline)
  LeadScore ensemble_5, baseline_5, imminent, ensemble_at_imminent, baseline_at_imminent;
  std::optional<double> p_star_all_5;                // p* chosen on every record (what an operator would set)
  CalibratedForecast calibrated_forecast;
};

// members: the ensemble's N (the clamp of logit P in the recalibration).
ForecastOutcome forecast_outcome(const StudyPlan& plan, const std::vector<ForecastRunResult>& results,
                                 int members = 100);

// Mean (p[i] − outcome[i])² over the forecasts (NaN when there are none).
double brier_score(const std::vector<double>& p, const std::vector<std::uint8_t>& outcome);

// Reliability of the forecasts p[i] against their outcomes: bins of width 0.1 ([lo, hi), the last closed), the empty
// ones left out; `judged` counts the bins with at least kCalibrationMinForecasts forecasts and `max_error` is their
// largest |observed − mean P| (none when no bin is judged).
std::vector<ReliabilityBin> reliability_bins(const std::vector<double>& p, const std::vector<std::uint8_t>& outcome,
                                             std::size_t& judged, std::optional<double>& max_error);

// The smallest p* on a 0.01 grid in (0, 1] reached (≥ p* − 1e-12) by at most `allowed` of the survivors' largest P;
// none when even 1.0 is reached by more.
std::optional<double> threshold_for(const std::vector<double>& survivor_maxima, std::size_t allowed);

}  // namespace rockwatch::sim::study
