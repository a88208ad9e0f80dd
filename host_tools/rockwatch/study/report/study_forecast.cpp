#include "study/report/study_forecast.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

nlohmann::ordered_json lead_json(const study::LeadScore& s, bool with_threshold) {
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

std::string lead_line(const study::LeadScore& s) {
  return format("false alarms %s (%zu/%zu), recall %s (%zu/%zu), lead median %s s (%s s, a miss as 0)",
                opt3(s.false_alarm_rate).c_str(), s.survivors_flagged, s.survivors, opt3(s.recall).c_str(),
                s.collapsed_flagged, s.collapsed, opt3(s.lead_time_s_median).c_str(),
                opt3(s.lead_time_s_median_all_collapses).c_str());
}

nlohmann::ordered_json bins_json(const std::vector<study::ReliabilityBin>& bins) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const study::ReliabilityBin& b : bins) {
    j.push_back({{"lo", b.lo}, {"hi", b.hi}, {"n", b.n}, {"mean_p", b.mean_p}, {"observed", b.observed}});
  }
  return j;
}

}  // namespace

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
                                             const study::ForecastOutcome& o) {
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
                      {"tolerance", study::kCalibrationTolerance},
                      {"min_forecasts_per_bin", study::kCalibrationMinForecasts}};
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
  const auto fitted = [folds](const study::LeadScore& l) { return folds ? lead_json(l, true) : nlohmann::ordered_json(nullptr); };
  j["lead"] = {{"ensemble_5_percent", fitted(o.ensemble_5)},
               {"baseline_5_percent", fitted(o.baseline_5)},
               {"imminent", lead_json(o.imminent, false)},
               {"ensemble_at_imminent_false_alarms", fitted(o.ensemble_at_imminent)},
               {"baseline_at_imminent_false_alarms", fitted(o.baseline_at_imminent)},
               {"p_star_5_percent_all_records", number_or_null(o.p_star_all_5)}};
  const study::CalibratedForecast& c = o.calibrated_forecast;
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
    const auto fitted_c = [&c](const study::LeadScore& l) {
      return c.fitted ? lead_json(l, true) : nlohmann::ordered_json(nullptr);
    };
    cj["lead"] = {{"calibrated_5_percent", fitted_c(c.at_5)},
                  {"calibrated_at_imminent_false_alarms", fitted_c(c.at_imminent)}};
    j["calibrated"] = cj;
  }
  // The goals, judged on the figures above; the lead on every collapse (a miss as 0 s), so that a threshold
  // that flags a few collapses cannot win by its median over those few. `goals` judges the calibrated P (what the
  // monitor publishes as p_collapse_calibrated); `goals_raw_ensemble` the raw one, beside it.
  const auto goals = [&o](bool calibrated, std::optional<double> skill, const study::LeadScore& e) {
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
                        const std::vector<study::ForecastRunResult>& results, const study::ForecastOutcome& outcome) {
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

std::string forecast_summary_text(const study::ForecastEvaluationPlan& e, const study::ForecastOutcome& o) {
  std::string out = format("\nEnsemble forecast evaluation (SPEC section 10): %zu forecasts of %zu runs (%zu collapse), "
                           "%d members, horizon %s s, every %s s; leave one record out (%zu records)\n",
                           o.forecasts, o.runs, o.collapsing_runs, e.settings.members,
                           number_text(e.settings.horizon_s).c_str(), number_text(e.every_s).c_str(), o.groups);
  line(out, "Brier", format("%s (base rate %s: %s), skill %s; baseline skill %s (in sample %s)", opt3(o.brier).c_str(),
                            opt3(o.base_rate).c_str(), opt3(o.brier_base_rate).c_str(), opt3(o.brier_skill).c_str(),
                            opt3(o.baseline_skill).c_str(), opt3(o.baseline_skill_in_sample).c_str()));
  line(out, "calibration", format("%s: max |observed - mean P| %s over %zu bins with >= %zu forecasts",
                                  o.calibrated ? "calibrated" : "NOT calibrated", opt3(o.calibration_max_error).c_str(),
                                  o.bins_judged, study::kCalibrationMinForecasts));
  if (o.groups < 2) {
    line(out, "baseline, p*", "not fitted: one record, none to leave out (give two or more records)");
  } else {
    line(out, "P >= p* (5 %)", lead_line(o.ensemble_5));
    line(out, "baseline (5 %)", lead_line(o.baseline_5));
  }
  line(out, "IMMINENT", lead_line(o.imminent));
  if (o.groups >= 2) {
    line(out, "P at IMMINENT's FA", lead_line(o.ensemble_at_imminent));
    const study::CalibratedForecast& c = o.calibrated_forecast;
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
