#include "study/statistics/study_forecast.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"
#include "study/statistics/study_summary.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

// One forecast, flattened, with the group (record name) its run belongs to.
struct Flat {
  std::size_t run = 0, group = 0;
  const study::ForecastPoint* point = nullptr;
};

constexpr int kFeatures = 3;  // 1, max E/E_barrier over 2 s, |x|/x_inst

double logistic(const double* w, const study::ForecastPoint& p) {
  const double z = w[0] + w[1] * p.energy_ratio_max + w[2] * p.x_over_x_inst;
  return 1.0 / (1.0 + std::exp(-std::clamp(z, -50.0, 50.0)));
}

// Maximum-likelihood logistic regression by Newton–Raphson (a 1e-6 ridge keeps the Hessian invertible when the
// classes separate), on the forecasts whose group is not `left_out` (every forecast when left_out is none).
std::vector<double> fit_logistic(const std::vector<Flat>& all, std::optional<std::size_t> left_out) {
  double w[kFeatures] = {0.0, 0.0, 0.0};
  for (int iteration = 0; iteration < 50; ++iteration) {
    double g[kFeatures] = {}, H[kFeatures][kFeatures + 1] = {};
    for (int a = 0; a < kFeatures; ++a) H[a][a] = 1e-6;
    for (const Flat& f : all) {
      if (left_out && f.group == *left_out) continue;
      const double x[kFeatures] = {1.0, f.point->energy_ratio_max, f.point->x_over_x_inst};
      const double p = logistic(w, *f.point);
      const double y = f.point->outcome ? 1.0 : 0.0;
      for (int a = 0; a < kFeatures; ++a) {
        g[a] += (y - p) * x[a];
        for (int b = 0; b < kFeatures; ++b) H[a][b] += p * (1.0 - p) * x[a] * x[b];
      }
    }
    for (int a = 0; a < kFeatures; ++a) H[a][kFeatures] = g[a];
    for (int c = 0; c < kFeatures; ++c) {  // Gauss–Jordan with partial pivoting
      int pivot = c;
      for (int r = c + 1; r < kFeatures; ++r) {
        if (std::fabs(H[r][c]) > std::fabs(H[pivot][c])) pivot = r;
      }
      for (int k = 0; k <= kFeatures; ++k) std::swap(H[c][k], H[pivot][k]);
      if (H[c][c] == 0.0) return {w[0], w[1], w[2]};
      for (int r = 0; r < kFeatures; ++r) {
        if (r == c) continue;
        const double m = H[r][c] / H[c][c];
        for (int k = c; k <= kFeatures; ++k) H[r][k] -= m * H[c][k];
      }
    }
    double largest = 0.0;
    for (int a = 0; a < kFeatures; ++a) {
      const double d = H[a][kFeatures] / H[a][a];
      w[a] += d;
      largest = std::max(largest, std::fabs(d));
    }
    if (largest < 1e-10) break;
  }
  return {w[0], w[1], w[2]};
}

double brier_of(const std::vector<Flat>& all, const std::vector<double>& p) {
  double sum = 0.0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const double d = p[i] - (all[i].point->outcome ? 1.0 : 0.0);
    sum += d * d;
  }
  return sum / double(all.size());
}

// The smallest p* on a 0.01 grid in (0, 1] reached by at most `allowed` of the survivors' maxima; none when even
// 1.0 is reached by more.
std::optional<double> threshold_for(const std::vector<double>& survivor_maxima, std::size_t allowed) {
  for (int k = 1; k <= 100; ++k) {
    const double p_star = k / 100.0;
    const auto reached = static_cast<std::size_t>(std::count_if(
        survivor_maxima.begin(), survivor_maxima.end(), [p_star](double m) { return m >= p_star - 1e-12; }));
    if (reached <= allowed) return p_star;
  }
  return std::nullopt;
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

nlohmann::ordered_json lead_json(const LeadScore& s, bool with_threshold) {
  nlohmann::ordered_json j;
  if (with_threshold) {
    j["p_star"] = {{"min", number_or_null(s.p_star_min)},
                   {"median", number_or_null(s.p_star_median)},
                   {"max", number_or_null(s.p_star_max)},
                   {"folds_without_threshold", s.folds_without_threshold}};
  }
  j["false_alarm_rate"] = number_or_null(s.false_alarm_rate);
  j["survivors"] = s.survivors;
  j["survivors_flagged"] = s.survivors_flagged;
  j["recall"] = number_or_null(s.recall);
  j["collapsed"] = s.collapsed;
  j["collapsed_flagged"] = s.collapsed_flagged;
  j["lead_time_s_median"] = number_or_null(s.lead_time_s_median);
  j["lead_time_s_p05"] = number_or_null(s.lead_time_s_p05);
  j["lead_time_s_median_all_collapses"] = number_or_null(s.lead_time_s_median_all_collapses);
  return j;
}

std::string opt3(const std::optional<double>& v) { return v ? format("%.3f", *v) : std::string("-"); }

std::string lead_line(const LeadScore& s) {
  return format("false alarms %s (%zu/%zu), recall %s (%zu/%zu), lead median %s s (%s s, a miss as 0)",
                opt3(s.false_alarm_rate).c_str(), s.survivors_flagged, s.survivors, opt3(s.recall).c_str(),
                s.collapsed_flagged, s.collapsed, opt3(s.lead_time_s_median).c_str(),
                opt3(s.lead_time_s_median_all_collapses).c_str());
}

// Reliability of the forecasts p[i] (bins of width 0.1, the last closed); returns the judged bins' count and largest
// error through the arguments.
std::vector<ReliabilityBin> reliability_of(const std::vector<Flat>& all, const std::vector<double>& p,
                                           std::size_t& judged, std::optional<double>& max_error) {
  std::vector<ReliabilityBin> bins;
  judged = 0;
  max_error.reset();
  for (int k = 0; k < 10; ++k) {
    ReliabilityBin b;
    b.lo = k / 10.0;
    b.hi = (k + 1) / 10.0;
    double sum_p = 0.0, sum_o = 0.0;
    for (std::size_t i = 0; i < all.size(); ++i) {
      const int bin = std::min(9, static_cast<int>(std::floor(p[i] * 10.0 + 1e-12)));
      if (bin != k) continue;
      ++b.n;
      sum_p += p[i];
      sum_o += all[i].point->outcome ? 1.0 : 0.0;
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

nlohmann::ordered_json bins_json(const std::vector<ReliabilityBin>& bins) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const ReliabilityBin& b : bins) {
    j.push_back({{"lo", b.lo}, {"hi", b.hi}, {"n", b.n}, {"mean_p", b.mean_p}, {"observed", b.observed}});
  }
  return j;
}

}  // namespace

ForecastOutcome forecast_outcome(const study::StudyPlan& plan, const std::vector<study::ForecastRunResult>& results,
                                 int members) {
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
    const study::ForecastRunResult& r = results[i];
    if (!r.done) continue;
    if (!r.error.empty()) {
      ++o.runs_with_error;
      continue;
    }
    ++o.runs;
    (r.collapsed ? o.collapsing_runs : o.surviving_runs) += 1;
    o.at_rest_skipped += r.at_rest;
    run_group[i] = group_of_record[study::forecast_run_key(plan, i).record_index];
    for (const study::ForecastPoint& p : r.points) all.push_back(Flat{i, run_group[i], &p});
  }
  o.forecasts = all.size();
  if (all.empty()) return o;

  std::size_t positives = 0;
  double brier_sum = 0.0;
  for (const Flat& f : all) {
    positives += f.point->outcome ? 1 : 0;
    const double d = f.point->p_collapse - (f.point->outcome ? 1.0 : 0.0);
    brier_sum += d * d;
  }
  const double base = double(positives) / double(all.size());
  o.base_rate = base;
  o.brier = brier_sum / double(all.size());
  o.brier_base_rate = base * (1.0 - base);  // the Brier score of forecasting the base rate everywhere
  if (*o.brier_base_rate > 0.0) o.brier_skill = 1.0 - *o.brier / *o.brier_base_rate;

  // Reliability.
  {
    std::vector<double> raw(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) raw[i] = all[i].point->p_collapse;
    o.bins = reliability_of(all, raw, o.bins_judged, o.calibration_max_error);
  }
  o.calibrated = o.bins_judged > 0 && *o.calibration_max_error <= kCalibrationTolerance;

  // The baseline, leave one group out.
  const std::vector<double> w_all = fit_logistic(all, std::nullopt);
  o.baseline_weights_in_sample = w_all;
  std::vector<double> in_sample(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) in_sample[i] = logistic(w_all.data(), *all[i].point);
  if (o.brier_skill) o.baseline_skill_in_sample = 1.0 - brier_of(all, in_sample) / *o.brier_base_rate;
  if (o.groups >= 2) {
    o.baseline_p.assign(all.size(), 0.0);
    for (std::size_t g = 0; g < o.groups; ++g) {
      bool any = false;
      for (const Flat& f : all) any = any || f.group == g;
      if (!any) continue;
      const std::vector<double> w = fit_logistic(all, g);
      for (std::size_t i = 0; i < all.size(); ++i) {
        if (all[i].group == g) o.baseline_p[i] = logistic(w.data(), *all[i].point);
      }
    }
    o.baseline_brier = brier_of(all, o.baseline_p);
    if (o.brier_skill) o.baseline_skill = 1.0 - *o.baseline_brier / *o.brier_base_rate;
    if (*o.baseline_brier > 0.0) o.skill_vs_baseline = 1.0 - *o.brier / *o.baseline_brier;
  }

  // The recalibrated P (SPEC §10): its coefficients on every record (in sample, what would ship) and per fold on the
  // other records only (the forecasts of the record left out are never among the rows that fit its fold).
  CalibratedForecast& cal = o.calibrated_forecast;
  {
    const std::size_t k = sim::kCalibrationFeatures;
    std::vector<double> x(all.size() * k);
    std::vector<std::uint8_t> y(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
      const study::ForecastPoint& p = *all[i].point;
      const auto f = sim::calibration_features(p.p_collapse, members, p.energy_ratio_max, p.x_over_x_inst);
      for (std::size_t a = 0; a < k; ++a) x[i * k + a] = f[a];
      y[i] = p.outcome ? 1 : 0;
    }
    const auto apply = [&](const std::vector<double>& w, std::size_t i) {
      double z = 0.0;
      for (std::size_t a = 0; a < k; ++a) z += w[a] * x[i * k + a];
      return 1.0 / (1.0 + std::exp(-std::clamp(z, -50.0, 50.0)));
    };
    cal.coefficients_all_records = sim::fit_logistic_regression(x, k, y);
    if (o.brier_base_rate && *o.brier_base_rate > 0.0) {
      std::vector<double> in(all.size());
      for (std::size_t i = 0; i < all.size(); ++i) in[i] = apply(cal.coefficients_all_records, i);
      cal.brier_skill_in_sample = 1.0 - brier_of(all, in) / *o.brier_base_rate;
    }
    if (o.groups >= 2) {
      cal.fitted = true;
      cal.p.assign(all.size(), 0.0);
      std::vector<std::uint8_t> use(all.size());
      for (std::size_t g = 0; g < o.groups; ++g) {
        bool any = false;
        for (std::size_t i = 0; i < all.size(); ++i) {
          use[i] = all[i].group != g ? 1 : 0;
          any = any || all[i].group == g;
        }
        if (!any) continue;
        ++cal.folds;
        const std::vector<double> w = sim::fit_logistic_regression(x, k, y, use);
        for (std::size_t i = 0; i < all.size(); ++i) {
          if (all[i].group != g) continue;
          cal.p[i] = apply(w, i);
          ++cal.fold_rows_checked;
        }
      }
      cal.brier = brier_of(all, cal.p);
      if (o.brier_base_rate && *o.brier_base_rate > 0.0) cal.brier_skill = 1.0 - *cal.brier / *o.brier_base_rate;
      if (o.baseline_brier && *o.baseline_brier > 0.0) cal.skill_vs_baseline = 1.0 - *cal.brier / *o.baseline_brier;
      cal.bins = reliability_of(all, cal.p, cal.bins_judged, cal.calibration_max_error);
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
    const study::ForecastRunResult& r = results[i];
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
        const study::ForecastRunResult& r = results[i];
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

nlohmann::ordered_json forecast_plan_json(const study::ForecastEvaluationPlan& e) {
  const sim::ForecastSettings& s = e.settings;
  return {{"members", s.members},       {"horizon_s", s.horizon_s},
          {"every_s", e.every_s},       {"seed", s.seed},
          {"step_s", s.step_s},         {"rest_speed_mps", s.rest_speed_mps},
          {"window_s", s.window_s},     {"block_s", s.block_s},
          {"damping", s.damping},       {"highpass_ratio", s.highpass_ratio},
          {"growth_min_per_s", s.growth_min_per_s}, {"growth_max_per_s", s.growth_max_per_s},
          {"sigma_now_cap", s.sigma_now_cap},       {"intensity_log_sigma", s.intensity_log_sigma},
          {"match_velocity", s.match_velocity},     {"default_sigma_fraction", s.default_sigma_fraction},
          {"intensity_ramp_s", s.intensity_ramp_s}, {"condition_on_record", s.condition_on_record},
          {"record_noise_var", s.record_noise_var}};
}

nlohmann::ordered_json forecast_summary_json(const study::ForecastEvaluationPlan& evaluation,
                                             const ForecastOutcome& o) {
  nlohmann::ordered_json j;
  j["settings"] = forecast_plan_json(evaluation);
  j["held_out"] = "leave one record out: the baseline's weights, the recalibration's coefficients and every "
                  "threshold p* are fitted on the other records' forecasts and runs (a record is its name: a suite set's X and Y are left out together); "
                  "the ensemble fits nothing to these records (its defaults were chosen on sets 1-3 of the shipped "
                  "suite, SPEC section 10)";
  j["runs"] = o.runs;
  j["runs_with_error"] = o.runs_with_error;
  j["collapsing_runs"] = o.collapsing_runs;
  j["surviving_runs"] = o.surviving_runs;
  j["record_groups"] = o.groups;
  j["forecasts"] = o.forecasts;
  j["at_rest_skipped"] = o.at_rest_skipped;
  j["base_rate"] = number_or_null(o.base_rate);
  j["brier"] = number_or_null(o.brier);
  j["brier_base_rate"] = number_or_null(o.brier_base_rate);
  j["brier_skill"] = number_or_null(o.brier_skill);
  j["reliability"] = bins_json(o.bins);
  j["calibration"] = {{"calibrated", o.calibrated},
                      {"bins_judged", o.bins_judged},
                      {"max_abs_error", number_or_null(o.calibration_max_error)},
                      {"tolerance", kCalibrationTolerance},
                      {"min_forecasts_per_bin", kCalibrationMinForecasts}};
  nlohmann::ordered_json weights = nullptr;
  if (o.baseline_weights_in_sample.size() == 3) {
    weights = {{"const", o.baseline_weights_in_sample[0]},
               {"energy_ratio_max_2s", o.baseline_weights_in_sample[1]},
               {"x_over_x_inst", o.baseline_weights_in_sample[2]}};
  }
  j["baseline"] = {{"brier", number_or_null(o.baseline_brier)},
                   {"brier_skill", number_or_null(o.baseline_skill)},
                   {"brier_skill_in_sample", number_or_null(o.baseline_skill_in_sample)},
                   {"weights_in_sample", weights}};
  j["brier_skill_vs_baseline"] = number_or_null(o.skill_vs_baseline);
  // With one record there is nothing to leave out: the fitted rules are not scored (null), IMMINENT is.
  const bool folds = o.groups >= 2;
  const auto fitted = [folds](const LeadScore& l) { return folds ? lead_json(l, true) : nlohmann::ordered_json(nullptr); };
  j["lead"] = {{"ensemble_5_percent", fitted(o.ensemble_5)},
               {"baseline_5_percent", fitted(o.baseline_5)},
               {"imminent", lead_json(o.imminent, false)},
               {"ensemble_at_imminent_false_alarms", fitted(o.ensemble_at_imminent)},
               {"baseline_at_imminent_false_alarms", fitted(o.baseline_at_imminent)},
               {"p_star_5_percent_all_records", number_or_null(o.p_star_all_5)}};
  const CalibratedForecast& c = o.calibrated_forecast;
  {
    nlohmann::ordered_json cj;
    cj["model"] = "P_cal = 1/(1 + exp(-(c0 + c1 L + c2 energy_ratio_max_2s + c3 x_over_x_inst + c4 L min("
                  "energy_ratio_max_2s, 2)))), L = logit(clamp(P, 0.5/N, 1 - 0.5/N)), maximum likelihood; leave one "
                  "record out (the baseline's folds)";
    nlohmann::ordered_json coef = nullptr;
    if (c.coefficients_all_records.size() == std::size_t(sim::kCalibrationFeatures)) {
      coef = {{"const", c.coefficients_all_records[0]},
              {"logit_p", c.coefficients_all_records[1]},
              {"energy_ratio_max_2s", c.coefficients_all_records[2]},
              {"x_over_x_inst", c.coefficients_all_records[3]},
              {"logit_p_x_energy_ratio_max_2s_capped", c.coefficients_all_records[4]}};
    }
    cj["coefficients_all_records"] = coef;
    cj["folds"] = c.folds;
    cj["brier"] = number_or_null(c.brier);
    cj["brier_skill"] = number_or_null(c.brier_skill);
    cj["brier_skill_in_sample"] = number_or_null(c.brier_skill_in_sample);
    cj["brier_skill_vs_baseline"] = number_or_null(c.skill_vs_baseline);
    cj["reliability"] = bins_json(c.bins);
    cj["calibration"] = {{"calibrated", c.calibrated},
                         {"bins_judged", c.bins_judged},
                         {"max_abs_error", number_or_null(c.calibration_max_error)}};
    const auto fitted_c = [&c](const LeadScore& l) {
      return c.fitted ? lead_json(l, true) : nlohmann::ordered_json(nullptr);
    };
    cj["lead"] = {{"calibrated_5_percent", fitted_c(c.at_5)},
                  {"calibrated_at_imminent_false_alarms", fitted_c(c.at_imminent)}};
    j["calibrated"] = cj;
  }
  // The goals, judged on the figures above; the lead on every collapse (a miss as 0 s), so that a threshold
  // that flags a few collapses cannot win by its median over those few. `goals` judges the calibrated P (what the
  // monitor publishes as p_collapse_calibrated); `goals_raw_ensemble` the raw one, beside it.
  const auto goals = [&o](bool calibrated, std::optional<double> skill, const LeadScore& e) {
    const bool fewer = e.survivors_flagged <= o.imminent.survivors_flagged;
    std::optional<double> gain;
    if (e.lead_time_s_median_all_collapses && o.imminent.lead_time_s_median_all_collapses) {
      gain = *e.lead_time_s_median_all_collapses - *o.imminent.lead_time_s_median_all_collapses;
    }
    return nlohmann::ordered_json{
        {"calibrated", calibrated},
        {"skill_above_baseline", skill && o.baseline_skill && *skill > *o.baseline_skill},
        {"longer_lead_than_imminent_at_no_more_false_alarms", fewer && gain && *gain > 0.0},
        {"median_lead_gain_over_imminent_s", number_or_null(gain)}};
  };
  j["goals"] = goals(c.calibrated, c.brier_skill, c.at_imminent);
  j["goals"]["judged"] = "the calibrated P (calibrated), leave one record out";
  j["goals_raw_ensemble"] = goals(o.calibrated, o.brier_skill, o.ensemble_at_imminent);
  j["definitions"] = {
      {"forecast", "P(collapse within horizon_s) from the run's own state at t_s (sim::EnsembleForecaster, SPEC "
                   "section 10), one every every_s while the wall moves, up to its collapse"},
      {"outcome", "the run (double engine) collapsed in (t_s, t_s + horizon_s]"},
      {"brier", "mean (P - outcome)^2 over every forecast"},
      {"brier_skill", "1 - brier / brier_base_rate, brier_base_rate = base_rate (1 - base_rate)"},
      {"reliability", "forecasts in bins of P of width 0.1 (the last closed): mean P and observed frequency"},
      {"calibrated", "|observed - mean_p| <= tolerance in every bin with >= min_forecasts_per_bin forecasts"},
      {"baseline", "logistic regression on (1, max E/E_barrier over the last 2 s of the run, |x|/x_inst at t_s), "
                   "maximum likelihood, leave one record out"},
      {"p_star", "per fold, the smallest multiple of 0.01 that at most 5 % of the other records' surviving runs "
                 "(or, at_imminent_false_alarms, at most as many as IMMINENT flagged among them) ever reach"},
      {"false_alarm_rate", "surviving runs that ever reach the rule / surviving runs"},
      {"lead_time", "t_collapse - the first forecast time the rule is reached, over collapses reached before "
                    "t_collapse (forecasts every every_s: lead times are multiples of it); "
                    "lead_time_s_median_all_collapses: over every collapse, a missed one counting 0 s"},
      {"goals", "judged on the calibrated P (calibrated.*; goals_raw_ensemble: the same on the raw ensemble's P): "
                "calibrated: as calibration; skill_above_baseline: brier_skill > baseline.brier_skill (both out of "
                "sample); longer_lead...: the rule at IMMINENT's false alarms flags no more survivors than IMMINENT and "
                "its lead_time_s_median_all_collapses is longer than IMMINENT's (median_lead_gain_over_imminent_s)"},
      {"calibrated", "the ensemble's P recalibrated with the state (SPEC section 10 'Calibrated P'): a logistic "
                     "regression on (1, logit of P clamped to [0.5/N, 1 - 0.5/N], max E/E_barrier over 2 s, "
                     "|x|/x_inst), fitted leave one record out on the same folds as the baseline"},
      {"imminent", "the alarm's first IMMINENT (checked every integration step), no fitted parameter"}};
  return j;
}

void write_forecast_csv(std::ostream& out, const study::StudyPlan& plan,
                        const std::vector<study::ForecastRunResult>& results, const ForecastOutcome& outcome) {
  out << "run,record,component,r,pga_g,t_s,p_collapse,p_collapse_se,q50_max_x_over_x_inst,q90_max_x_over_x_inst,"
         "energy_ratio_max_2s,x_over_x_inst,imminent,outcome,baseline_p,collapsed,t_collapse_s,p_calibrated\n";
  std::size_t k = 0;  // index of the forecast in outcome.baseline_p (the order of forecast_outcome)
  for (std::size_t i = 0; i < results.size(); ++i) {
    const study::ForecastRunResult& r = results[i];
    if (!r.done || !r.error.empty()) continue;
    const study::ForecastRunKey key = study::forecast_run_key(plan, i);
    const study::StudyRecord& rec = plan.records[key.record_index];
    const std::string prefix = std::to_string(i) + ',' + rec.name + ',' + rec.component + ',' +
                               plan.restitutions[key.restitution_index].label + ',' +
                               number_text(plan.pga_g[key.pga_index]) + ',';
    const std::string suffix =
        std::string(r.collapsed ? "true" : "false") + ',' + (r.t_collapse_s ? number_text(*r.t_collapse_s) : "") + ',';
    for (const study::ForecastPoint& p : r.points) {
      out << prefix << number_text(p.t_s) << ',' << number_text(p.p_collapse) << ',' << number_text(p.p_collapse_se)
          << ',' << number_text(p.q50_max_x_over_x_inst) << ',' << number_text(p.q90_max_x_over_x_inst) << ','
          << number_text(p.energy_ratio_max) << ',' << number_text(p.x_over_x_inst) << ','
          << (p.imminent ? "true" : "false") << ',' << (p.outcome ? 1 : 0) << ','
          << (outcome.baseline_p.empty() ? std::string() : number_text(outcome.baseline_p[k])) << ',' << suffix
          << (outcome.calibrated_forecast.p.empty() ? std::string() : number_text(outcome.calibrated_forecast.p[k]))
          << '\n';
      ++k;
    }
  }
}

std::string forecast_summary_text(const study::ForecastEvaluationPlan& e, const ForecastOutcome& o) {
  std::string out = format("\nEnsemble forecast evaluation (SPEC section 10): %zu forecasts of %zu runs (%zu collapse), "
                           "%d members, horizon %s s, every %s s; leave one record out (%zu records)\n",
                           o.forecasts, o.runs, o.collapsing_runs, e.settings.members,
                           number_text(e.settings.horizon_s).c_str(), number_text(e.every_s).c_str(), o.groups);
  line(out, "Brier", format("%s (base rate %s: %s), skill %s; baseline skill %s (in sample %s)", opt3(o.brier).c_str(),
                            opt3(o.base_rate).c_str(), opt3(o.brier_base_rate).c_str(), opt3(o.brier_skill).c_str(),
                            opt3(o.baseline_skill).c_str(), opt3(o.baseline_skill_in_sample).c_str()));
  line(out, "calibration", format("%s: max |observed - mean P| %s over %zu bins with >= %zu forecasts",
                                  o.calibrated ? "calibrated" : "NOT calibrated", opt3(o.calibration_max_error).c_str(),
                                  o.bins_judged, kCalibrationMinForecasts));
  if (o.groups < 2) {
    line(out, "baseline, p*", "not fitted: one record, none to leave out (give two or more records)");
  } else {
    line(out, "P >= p* (5 %)", lead_line(o.ensemble_5));
    line(out, "baseline (5 %)", lead_line(o.baseline_5));
  }
  line(out, "IMMINENT", lead_line(o.imminent));
  if (o.groups >= 2) {
    line(out, "P at IMMINENT's FA", lead_line(o.ensemble_at_imminent));
    const CalibratedForecast& c = o.calibrated_forecast;
    line(out, "calibrated P", format("Brier %s, skill %s (raw %s, baseline %s); %s: max |observed - mean P| %s",
                                     opt3(c.brier).c_str(), opt3(c.brier_skill).c_str(), opt3(o.brier_skill).c_str(),
                                     opt3(o.baseline_skill).c_str(), c.calibrated ? "calibrated" : "NOT calibrated",
                                     opt3(c.calibration_max_error).c_str()));
    line(out, "calibrated (5 %)", lead_line(c.at_5));
    line(out, "calibrated at FA", lead_line(c.at_imminent));
  }
  return out;
}

}  // namespace rockwatch::cli
