#include "rockwatch/sim/study/forecast_scores.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/sim/study/logistic_fit.hpp"
#include "rockwatch/sim/study/quantile.hpp"

namespace rockwatch::sim::study {

double brier_score(const std::vector<double>& p, const std::vector<std::uint8_t>& outcome) {
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = p[i] - (outcome[i] ? 1.0 : 0.0);
    sum += d * d;
  }
  return sum / double(p.size());
}

std::vector<ReliabilityBin> reliability_bins(const std::vector<double>& p, const std::vector<std::uint8_t>& outcome,
                                             std::size_t& judged, std::optional<double>& max_error) {
  std::vector<ReliabilityBin> bins;
  judged = 0;
  max_error.reset();
  for (int k = 0; k < 10; ++k) {
    ReliabilityBin b;
    b.lo = k / 10.0;
    b.hi = (k + 1) / 10.0;
    double sum_p = 0.0, sum_o = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const int bin = std::min(9, static_cast<int>(std::floor(p[i] * 10.0 + 1e-12)));
      if (bin != k) continue;
      ++b.n;
      sum_p += p[i];
      sum_o += outcome[i] ? 1.0 : 0.0;
    }
    if (b.n == 0) continue;
    b.mean_p = sum_p / double(b.n);
    b.observed = sum_o / double(b.n);
    if (b.n >= kCalibrationMinForecasts) {
      ++judged;
      max_error = std::max(max_error.value_or(0.0), std::fabs(b.observed - b.mean_p));
    }
    bins.push_back(b);
  }
  return bins;
}


std::optional<double> threshold_for(const std::vector<double>& survivor_maxima, std::size_t allowed) {
  for (int k = 1; k <= 100; ++k) {
    const double p_star = k / 100.0;
    const auto reached = static_cast<std::size_t>(std::count_if(
        survivor_maxima.begin(), survivor_maxima.end(), [p_star](double m) { return m >= p_star - 1e-12; }));
    if (reached <= allowed) return p_star;
  }
  return std::nullopt;
}

namespace {

// One forecast, flattened, with the group (record name) its run belongs to.
struct Flat {
  std::size_t run = 0, group = 0;
  const ForecastPoint* point = nullptr;
};

constexpr std::size_t kBaselineFeatures = 3;  // 1, max E/E_barrier over 2 s, |x|/x_inst

struct FoldCounts {
  std::size_t folds = 0, rows = 0;
};

// Leave one group out: for each group with forecasts, the weights fitted on the other groups' rows only
// (fit(use), use[i] = 0 on the group's rows) give the group's rows their probability p[i] = apply(w, i).
template <class Fit, class Apply>
FoldCounts leave_one_group_out(const std::vector<Flat>& all, std::size_t groups, std::vector<double>& p, Fit fit,
                               Apply apply) {
  FoldCounts counts;
  std::vector<std::uint8_t> use(all.size());
  for (std::size_t g = 0; g < groups; ++g) {
    bool any = false;
    for (std::size_t i = 0; i < all.size(); ++i) {
      use[i] = all[i].group != g ? 1 : 0;
      any = any || all[i].group == g;
    }
    if (!any) continue;
    ++counts.folds;
    const std::vector<double> w = fit(use);
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (all[i].group != g) continue;
      p[i] = apply(w, i);
      ++counts.rows;
    }
  }
  return counts;
}

void finish(LeadScore& s, std::vector<double>& thresholds) {
  if (s.survivors > 0) s.false_alarm_rate = double(s.survivors_flagged) / double(s.survivors);
  if (s.collapsed > 0) s.recall = double(s.collapsed_flagged) / double(s.collapsed);
  std::sort(s.lead_times_s.begin(), s.lead_times_s.end());
  s.lead_time_s_median = quantile_type7(s.lead_times_s, 0.5);
  s.lead_time_s_p05 = quantile_type7(s.lead_times_s, 0.05);
  std::vector<double> all(s.collapsed - s.collapsed_flagged, 0.0);  // the missed collapses: 0 s (ascending first)
  all.insert(all.end(), s.lead_times_s.begin(), s.lead_times_s.end());
  s.lead_time_s_median_all_collapses = quantile_type7(all, 0.5);
  std::sort(thresholds.begin(), thresholds.end());
  if (!thresholds.empty()) {
    s.p_star_min = thresholds.front();
    s.p_star_median = quantile_type7(thresholds, 0.5);
    s.p_star_max = thresholds.back();
  }
}

}  // namespace

ForecastOutcome forecast_outcome(const StudyPlan& plan, const std::vector<ForecastRunResult>& results, int members) {
  ForecastOutcome o;
  // Groups: the record's name (a suite's set: X and Y together).
  std::map<std::string, std::size_t> group_of_name;
  std::vector<std::size_t> group_of_record(plan.records.size());
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    const auto it = group_of_name.emplace(plan.records[i].name, group_of_name.size()).first;
    group_of_record[i] = it->second;
  }
  o.groups = group_of_name.size();
  std::vector<std::size_t> run_group(results.size(), 0);
  std::vector<Flat> all;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const ForecastRunResult& r = results[i];
    if (!r.done) continue;
    if (!r.error.empty()) {
      ++o.runs_with_error;
      continue;
    }
    ++o.runs;
    (r.collapsed ? o.collapsing_runs : o.surviving_runs) += 1;
    o.at_rest_skipped += r.at_rest;
    run_group[i] = group_of_record[forecast_run_key(plan, i).record_index];
    for (const ForecastPoint& p : r.points) all.push_back(Flat{i, run_group[i], &p});
  }
  o.forecasts = all.size();
  if (all.empty()) return o;

  // Per forecast: the ensemble's P, the outcome, the baseline's features (1, max E/E_barrier, |x|/x_inst).
  std::vector<double> raw(all.size()), baseline_x(all.size() * kBaselineFeatures);
  std::vector<std::uint8_t> outcome(all.size());
  std::size_t positives = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const ForecastPoint& p = *all[i].point;
    raw[i] = p.p_collapse;
    outcome[i] = p.outcome ? 1 : 0;
    positives += outcome[i];
    const double features[kBaselineFeatures] = {1.0, p.energy_ratio_max, p.x_over_x_inst};
    std::copy(features, features + kBaselineFeatures, &baseline_x[i * kBaselineFeatures]);
  }
  const double base = double(positives) / double(all.size());
  o.base_rate = base;
  o.brier = brier_score(raw, outcome);
  o.brier_base_rate = base * (1.0 - base);  // the Brier score of forecasting the base rate everywhere
  if (*o.brier_base_rate > 0.0) o.brier_skill = 1.0 - *o.brier / *o.brier_base_rate;

  // Reliability.
  o.bins = reliability_bins(raw, outcome, o.bins_judged, o.calibration_max_error);
  o.calibrated = o.bins_judged > 0 && *o.calibration_max_error <= kCalibrationTolerance;

  // The baseline, leave one group out.
  const auto baseline_at = [&](const std::vector<double>& w, std::size_t i) {
    return logistic_probability(w, &baseline_x[i * kBaselineFeatures]);
  };
  const std::vector<double> w_all = fit_logistic(baseline_x, kBaselineFeatures, outcome);
  o.baseline_weights_in_sample = w_all;
  std::vector<double> in_sample(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) in_sample[i] = baseline_at(w_all, i);
  if (o.brier_skill) o.baseline_skill_in_sample = 1.0 - brier_score(in_sample, outcome) / *o.brier_base_rate;
  if (o.groups >= 2) {
    o.baseline_p.assign(all.size(), 0.0);
    leave_one_group_out(
        all, o.groups, o.baseline_p,
        [&](const std::vector<std::uint8_t>& use) { return fit_logistic(baseline_x, kBaselineFeatures, outcome, use); },
        baseline_at);
    o.baseline_brier = brier_score(o.baseline_p, outcome);
    if (o.brier_skill) o.baseline_skill = 1.0 - *o.baseline_brier / *o.brier_base_rate;
    if (*o.baseline_brier > 0.0) o.skill_vs_baseline = 1.0 - *o.brier / *o.baseline_brier;
  }

  // The recalibrated P (SPEC §10): its coefficients on every record (in sample, what would ship) and per fold on the
  // other records only (the forecasts of the record left out are never among the rows that fit its fold).
  CalibratedForecast& cal = o.calibrated_forecast;
  {
    const std::size_t k = kCalibrationFeatures;
    std::vector<double> x(all.size() * k);
    for (std::size_t i = 0; i < all.size(); ++i) {
      const ForecastPoint& p = *all[i].point;
      const auto f = calibration_features(p.p_collapse, members, p.energy_ratio_max, p.x_over_x_inst);
      for (std::size_t a = 0; a < k; ++a) x[i * k + a] = f[a];
    }
    const auto apply = [&](const std::vector<double>& w, std::size_t i) { return logistic_probability(w, &x[i * k]); };
    cal.coefficients_all_records = fit_logistic_regression(x, k, outcome);
    if (o.brier_base_rate && *o.brier_base_rate > 0.0) {
      std::vector<double> in(all.size());
      for (std::size_t i = 0; i < all.size(); ++i) in[i] = apply(cal.coefficients_all_records, i);
      cal.brier_skill_in_sample = 1.0 - brier_score(in, outcome) / *o.brier_base_rate;
    }
    if (o.groups >= 2) {
      cal.fitted = true;
      cal.p.assign(all.size(), 0.0);
      const FoldCounts folds = leave_one_group_out(
          all, o.groups, cal.p,
          [&](const std::vector<std::uint8_t>& use) { return fit_logistic_regression(x, k, outcome, use); }, apply);
      cal.folds = folds.folds;
      cal.fold_rows_checked = folds.rows;
      cal.brier = brier_score(cal.p, outcome);
      if (o.brier_base_rate && *o.brier_base_rate > 0.0) cal.brier_skill = 1.0 - *cal.brier / *o.brier_base_rate;
      if (o.baseline_brier && *o.baseline_brier > 0.0) cal.skill_vs_baseline = 1.0 - *cal.brier / *o.baseline_brier;
      cal.bins = reliability_bins(cal.p, outcome, cal.bins_judged, cal.calibration_max_error);
      cal.calibrated = cal.bins_judged > 0 && *cal.calibration_max_error <= kCalibrationTolerance;
    }
  }

  // Per run: the largest P (ensemble, baseline, calibrated) over its forecasts; the first time each reaches a
  // threshold is found below from the forecasts in order.
  std::vector<double> run_max_p(results.size(), 0.0), run_max_b(results.size(), 0.0),
      run_max_c(results.size(), 0.0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    run_max_p[all[i].run] = std::max(run_max_p[all[i].run], all[i].point->p_collapse);
    if (!o.baseline_p.empty()) run_max_b[all[i].run] = std::max(run_max_b[all[i].run], o.baseline_p[i]);
    if (!cal.p.empty()) run_max_c[all[i].run] = std::max(run_max_c[all[i].run], cal.p[i]);
  }
  std::vector<std::size_t> scored;  // runs with results
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (results[i].done && results[i].error.empty()) scored.push_back(i);
  }
  // IMMINENT (nothing fitted).
  for (const std::size_t i : scored) {
    const ForecastRunResult& r = results[i];
    if (!r.collapsed) {
      ++o.imminent.survivors;
      if (r.t_first_imminent_s) ++o.imminent.survivors_flagged;
    } else {
      ++o.imminent.collapsed;
      if (r.t_first_imminent_s && r.t_collapse_s && *r.t_first_imminent_s < *r.t_collapse_s) {
        ++o.imminent.collapsed_flagged;
        o.imminent.lead_times_s.push_back(*r.t_collapse_s - *r.t_first_imminent_s);
      }
    }
  }
  {
    std::vector<double> none;
    finish(o.imminent, none);
  }
  {  // p* on every record (not an out-of-sample figure: what an operator would set from this study)
    std::vector<double> maxima;
    for (const std::size_t i : scored) {
      if (!results[i].collapsed) maxima.push_back(run_max_p[i]);
    }
    o.p_star_all_5 =
        threshold_for(maxima, static_cast<std::size_t>(std::floor(kLeadFalseAlarmFraction * double(maxima.size()))));
  }
  if (o.groups < 2) return o;

  // Index of each run's first forecast in `all` (forecasts of a run are consecutive, in time order).
  std::vector<std::size_t> first(results.size(), all.size()), count(results.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (count[all[i].run]++ == 0) first[all[i].run] = i;
  }
  // A rule "key ≥ p*" chosen per fold on the other groups' survivors, applied to the fold's runs.
  enum class Rule { ensemble, baseline, calibrated };
  auto score_rule = [&](LeadScore& s, Rule rule, bool at_imminent_rate) {
    const std::vector<double>& run_max =
        rule == Rule::baseline ? run_max_b : (rule == Rule::calibrated ? run_max_c : run_max_p);
    std::vector<double> thresholds;
    for (std::size_t g = 0; g < o.groups; ++g) {
      std::vector<double> maxima;
      std::size_t imminent_flagged = 0;
      bool fold_has_runs = false;
      for (const std::size_t i : scored) {
        if (run_group[i] == g) {
          fold_has_runs = true;
          continue;
        }
        if (results[i].collapsed) continue;
        maxima.push_back(run_max[i]);
        if (results[i].t_first_imminent_s) ++imminent_flagged;
      }
      if (!fold_has_runs) continue;
      const std::size_t allowed =
          at_imminent_rate ? imminent_flagged
                           : static_cast<std::size_t>(std::floor(kLeadFalseAlarmFraction * double(maxima.size())));
      const std::optional<double> p_star = threshold_for(maxima, allowed);
      if (p_star) {
        thresholds.push_back(*p_star);
      } else {
        ++s.folds_without_threshold;
      }
      for (const std::size_t i : scored) {
        if (run_group[i] != g) continue;
        const ForecastRunResult& r = results[i];
        std::optional<double> t_first;
        if (p_star) {
          for (std::size_t k = first[i]; k < first[i] + count[i]; ++k) {
            const double key = rule == Rule::baseline     ? o.baseline_p[k]
                               : rule == Rule::calibrated ? cal.p[k]
                                                          : all[k].point->p_collapse;
            if (key >= *p_star - 1e-12) {
              t_first = all[k].point->t_s;
              break;
            }
          }
        }
        if (!r.collapsed) {
          ++s.survivors;
          if (t_first) ++s.survivors_flagged;
        } else {
          ++s.collapsed;
          if (t_first && r.t_collapse_s && *t_first < *r.t_collapse_s) {
            ++s.collapsed_flagged;
            s.lead_times_s.push_back(*r.t_collapse_s - *t_first);
          }
        }
      }
    }
    finish(s, thresholds);
  };
  score_rule(o.ensemble_5, Rule::ensemble, false);
  score_rule(o.baseline_5, Rule::baseline, false);
  score_rule(o.ensemble_at_imminent, Rule::ensemble, true);
  score_rule(o.baseline_at_imminent, Rule::baseline, true);
  score_rule(cal.at_5, Rule::calibrated, false);
  score_rule(cal.at_imminent, Rule::calibrated, true);
  return o;
}


}  // namespace rockwatch::sim::study
