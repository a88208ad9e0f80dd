#include "study/report/study_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "common/records_in/shipped_suite.hpp"
#include "common/process/text_report.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

constexpr const char* kSpectrumProvenance =
    "npr9998-2015 spectrum, back-calculated from the design paper's static results (NPR 9998:2015 bedrock "
    "parameters are not public)";

// The runs of one case with a verdict, as the statistics take them.
std::vector<study::RunOutcome> case_runs(const study::StudyPlan& plan, const std::vector<study::RunResult>& results,
                                         const StudyCase& c, std::size_t& errors) {
  std::vector<study::RunOutcome> runs;
  for (std::size_t record = 0; record < plan.records.size(); ++record) {
    for (std::size_t level = 0; level < plan.pga_g.size(); ++level) {
      const study::RunKey key{c.vertical_index, c.restitution_index, record, level};
      const study::RunResult& r = results[study::run_index(plan, key)];
      if (!r.error.empty()) {
        ++errors;
        continue;
      }
      runs.push_back(study::RunOutcome{record, plan.pga_g[level], r.collapsed});
    }
  }
  return runs;
}

nlohmann::ordered_json value_or_null(bool ok, double value) {
  return ok ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json case_json(const study::StudyPlan& plan, const CaseOutcome& c) {
  nlohmann::ordered_json j;
  j["title"] = c.title;
  j["vertical"] = static_cast<bool>(plan.vertical[c.study_case.vertical_index]);
  j["r"] = restitution_json(plan.restitutions[c.study_case.restitution_index]);
  j["r_value"] = c.r_value;
  const study::CaseStatistics empty;
  const study::CaseStatistics& s = c.statistics ? *c.statistics : empty;
  j["n_runs"] = s.n_runs;
  j["runs_with_error"] = c.runs_with_error;
  j["min_pga_collapse_g"] = number_or_null(s.min_pga_collapse_g);
  j["fit_mean_g"] = value_or_null(s.normal.ok, s.normal.mean_g);
  j["fit_std_g"] = value_or_null(s.normal.ok, s.normal.std_g);
  j["fit_ok"] = s.normal.ok;
  j["fit_sum_squared_residuals"] = value_or_null(s.normal.ok, s.normal.sum_squared_residuals);
  nlohmann::ordered_json survival = nlohmann::ordered_json::array();
  for (const study::SurvivalPoint& p : s.survival) {
    survival.push_back(
        {{"pga_g", p.pga_g}, {"survival_rate", p.survival_rate}, {"runs", p.runs}, {"collapsed", p.collapsed}});
  }
  j["survival"] = survival;
  const char* const codes[] = {"ntc2008", "nzsee2016"};
  for (int i = 0; i < 2; ++i) {
    const study::CollapseProbability& p = i == 0 ? s.at_ntc2008 : s.at_nzsee2016;
    const std::string key = std::string("p_collapse_") + codes[i];
    j[key] = number_or_null(p.normal_fit);
    j[key + "_lognormal"] = number_or_null(p.lognormal_fit);
    j[key + "_empirical"] = number_or_null(p.empirical);
  }
  const study::LognormalFit& l = s.lognormal;
  nlohmann::ordered_json lognormal;
  lognormal["ok"] = l.ok;
  lognormal["median_g"] = value_or_null(l.ok, l.median_g);
  lognormal["beta"] = value_or_null(l.ok, l.beta);
  const bool ci = l.ok && l.bootstrap_samples > 0;
  lognormal["median_ci90_g"] = ci ? nlohmann::ordered_json{l.median_ci90_low_g, l.median_ci90_high_g}
                                  : nlohmann::ordered_json(nullptr);
  lognormal["beta_ci90"] = ci ? nlohmann::ordered_json{l.beta_ci90_low, l.beta_ci90_high} : nlohmann::ordered_json(nullptr);
  lognormal["bootstrap_samples"] = l.bootstrap_samples;
  j["lognormal"] = lognormal;
  j["resurrections"] = s.resurrections;
  return j;
}

nlohmann::ordered_json runs_json(const std::vector<std::size_t>& runs) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const std::size_t index : runs) j.push_back(index);
  return j;
}

nlohmann::ordered_json alarm_json(const study::StudyPlan& plan, const study::AlarmOutcome& a) {
  const core::AlarmSettings& s = plan.analysis.alarm;
  nlohmann::ordered_json j = alarm_score_json(a);
  j["settings"] = {{"lambda_warning", s.lambda_warning}, {"hold_s", s.hold_s}, {"energy_margin", s.energy_margin}};
  if (s.imminent_horizon_s > 0.0) j["settings"]["imminent_horizon_s"] = s.imminent_horizon_s;  // opt-in, SPEC §11
  if (s.energy_min_x > 0.0) j["settings"]["energy_min_x"] = s.energy_min_x;                    // when not 0, SPEC §11
  j["alarm_engine"] = arithmetic_name(plan.analysis.arithmetic);
  j["definitions"] = {
      {"verdict", "the double engine's (collapsed or collapsed after the record)"},
      {"recall", "collapsed runs flagged IMMINENT strictly before t_collapse / collapsed runs"},
      {"false_alarm_rate", "surviving runs ever flagged IMMINENT / surviving runs"},
      {"lead_time", "t_collapse - first IMMINENT over the collapsed runs flagged before t_collapse"},
      {"percentile", "linear interpolation between order statistics (Hyndman-Fan type 7, NumPy's default)"}};
  return j;
}

nlohmann::ordered_json fixed_json(const study::StudyPlan& plan, const study::FixedComparison& f) {
  nlohmann::ordered_json j;
  j["runs_compared"] = f.runs_compared;
  j["verdicts_same"] = f.verdicts_same;
  j["verdict_flips"] = runs_json(f.verdict_flips);
  j["flips_also_at_reference"] =
      plan.dt_check ? runs_json(f.flips_also_at_reference) : nlohmann::ordered_json(nullptr);
  j["max_abs_x_diff_m_max"] = number_or_null(f.max_abs_x_diff_m_max);
  j["survivors_compared"] = f.survivors_compared;
  j["survivors_within_0_5_mm"] = f.survivors_within_half_mm;
  j["first_imminent_diff_samples_max"] = f.first_imminent_diff_samples_max
                                             ? nlohmann::ordered_json(*f.first_imminent_diff_samples_max)
                                             : nlohmann::ordered_json(nullptr);
  j["imminent_compared"] = f.imminent_compared;
  j["imminent_within_one_step"] = f.imminent_within_one_step;
  j["runs_saturated"] = f.runs_saturated;
  return j;
}

std::string g_text(double value_g) { return format("%.3f g", value_g); }

std::string optional_g_text(const std::optional<double>& value_g, const char* when_absent) {
  return value_g ? g_text(*value_g) : std::string(when_absent);
}

std::string levels_text(const study::StudyPlan& plan) {
  const std::size_t n = plan.pga_g.size();
  if (n == 1) return number_text(plan.pga_g.front()) + " g (1 level)";
  return number_text(plan.pga_g.front()) + " to " + number_text(plan.pga_g.back()) + " g by " +
         number_text(std::round((plan.pga_g[1] - plan.pga_g[0]) * 1e12) / 1e12) + " g (" + std::to_string(n) +
         " levels)";
}

std::string wall_text(const StudyRequest& q) {
  const core::WallParameters& w = q.wall.wall;
  std::string text = q.wall.name + " wall";
  if (!q.wall.options_given.empty()) {
    text += " with";
    for (const std::string& o : q.wall.options_given) text += " " + o;
  }
  return text + format(": b %s m, h1 %s m, h2 %s m, rho %s kg/m3, Fp %s N/m, a %s, a' %s", number_text(w.b_m).c_str(),
                       number_text(w.h1_m).c_str(), number_text(w.h2_m).c_str(), number_text(w.rho_kgpm3).c_str(),
                       number_text(w.fp_npm).c_str(), number_text(w.a).c_str(), number_text(w.a_prime).c_str());
}

std::string probabilities_text(const study::CollapseProbability& p) {
  return probability_text(p.normal_fit) + " (normal fit; lognormal " + probability_text(p.lognormal_fit) +
         ", empirical " + probability_text(p.empirical) + ")";
}

void case_text(std::string& out, const StudyOutcome& o, const CaseOutcome& c) {
  const study::CaseStatistics empty;
  const study::CaseStatistics& s = c.statistics ? *c.statistics : empty;
  out += "\nCase " + c.title + format(" (r = %.4f): %zu run%s", c.r_value, s.n_runs, s.n_runs == 1 ? "" : "s");
  if (c.runs_with_error > 0) out += format(", %zu refused by the engine (no verdict)", c.runs_with_error);
  out += "\n";
  line(out, "min PGA collapse", optional_g_text(s.min_pga_collapse_g, "none: no run collapsed"));
  line(out, "normal fit (paper)", s.normal.ok ? "mean " + g_text(s.normal.mean_g) + ", sd " + g_text(s.normal.std_g)
                                              : std::string("undetermined (no or only collapses)"));
  line(out, "P(collapse) NTC 2008", "at " + g_text(o.capacities.ntc2008_g) + ": " + probabilities_text(s.at_ntc2008));
  line(out, "P(collapse) NZSEE 2016",
       "at " + g_text(o.capacities.nzsee2016_g) + ": " + probabilities_text(s.at_nzsee2016));
  const study::LognormalFit& l = s.lognormal;
  std::string lognormal = "undetermined";
  if (l.ok) {
    lognormal = "median " + g_text(l.median_g) + format(", beta %.3f", l.beta);
    if (l.bootstrap_samples > 0) {
      lognormal += format("; 90 %% CI median %.3f-%.3f g, beta %.3f-%.3f (%zu bootstrap samples)", l.median_ci90_low_g,
                          l.median_ci90_high_g, l.beta_ci90_low, l.beta_ci90_high, l.bootstrap_samples);
    }
  }
  line(out, "lognormal (MLE)", lognormal);
  line(out, "resurrections", std::to_string(s.resurrections) + " (survived above a PGA that collapsed the record)");
}

}  // namespace

std::string probability_text(const std::optional<double>& p) { return p ? format("%.3f", *p) : std::string("-"); }

const study::CollapseProbability& at_capacity(const study::CaseStatistics& s, bool nzsee2016) {
  return nzsee2016 ? s.at_nzsee2016 : s.at_ntc2008;
}

std::string run_text(const study::StudyPlan& plan, std::size_t index) {
  const study::RunKey key = study::run_key(plan, index);
  const study::StudyRecord& record = plan.records[key.record_index];
  std::string text = record.name + (record.component.empty() ? "" : " " + record.component);
  text += std::string(plan.vertical[key.vertical_index] ? ", H+V" : ", H-only") + ", r_" +
          plan.restitutions[key.restitution_index].label + ", " + number_text(plan.pga_g[key.pga_index]) + " g (run " +
          std::to_string(index) + ")";
  return text;
}

nlohmann::ordered_json published_json(const study::PublishedAlarm& p) {
  nlohmann::ordered_json j;
  j["work_budget_units"] = p.work_budget_units;
  j["recall"] = number_or_null(p.recall);
  j["false_alarm_rate"] = number_or_null(p.false_alarm_rate);
  j["lead_time_s_median"] = number_or_null(p.lead_time_s_median);
  j["lead_time_s_min"] = number_or_null(p.lead_time_s_min);
  j["imminent_delay_s_max"] = number_or_null(p.imminent_delay_s_max);
  j["runs_imminent_delayed"] = p.runs_imminent_delayed;
  j["runs_with_late_samples"] = p.runs_late;
  j["max_late_samples"] = p.max_late_samples;
  j["shed_samples"] = p.shed_samples;
  j["work_overflow"] = work_overflow_name(p.work_overflow);
  j["overrun_calls"] = p.overrun_calls;
  j["runs_with_overruns"] = p.runs_overrun;
  j["max_call_units"] = p.max_call_units;
  j["counts"] = {{"collapsed", p.collapsed},
                 {"collapsed_flagged", p.collapsed_flagged},
                 {"survivors", p.survivors},
                 {"survivors_flagged", p.survivors_flagged}};
  j["definitions"] = {
      {"published", "the monitor's engine does at most work_budget_units of work per input sample's call; a sample "
                    "whose work does not fit is published at a later sample's call (same answers, later)"},
      {"recall", "collapsed runs whose first IMMINENT is published strictly before t_collapse / collapsed runs"},
      {"imminent_delay_s_max", "publication of the first IMMINENT - the step end it was computed for, at most"},
      {"max_late_samples", "the most input samples a sample waited to be published, over the runs"},
      {"work_overflow", "at a full queue of waiting samples the engine sheds (events not located: every call within "
                        "the budget) or finishes the oldest beyond the budget (an overrun: the answers as computed)"},
      {"max_call_units", "the most work units one call did, an overrun's included (units = Cortex-M4 instructions)"}};
  return j;
}

nlohmann::ordered_json alarm_score_json(const study::AlarmOutcome& a) {
  nlohmann::ordered_json j;
  j["recall"] = number_or_null(a.recall);
  j["false_alarm_rate"] = number_or_null(a.false_alarm_rate);
  j["lead_time_s_median"] = number_or_null(a.lead_time_s_median);
  j["lead_time_s_p05"] = number_or_null(a.lead_time_s_p05);
  j["lead_time_s_min"] = number_or_null(a.lead_time_s_min);
  j["counts"] = {{"runs", a.runs},
                 {"collapsed", a.collapsed},
                 {"collapsed_flagged", a.collapsed_flagged},
                 {"survivors", a.survivors},
                 {"survivors_flagged", a.survivors_flagged}};
  return j;
}

StudyOutcome summarise_study(const study::StudyPlan& plan, const std::vector<study::RunResult>& results,
                             const StaticCapacities& capacities) {
  StudyOutcome o;
  o.capacities = capacities;
  for (const StudyCase& c : study_cases(plan)) {
    CaseOutcome co;
    co.study_case = c;
    co.title = case_title(plan, c);
    co.tag = case_tag(plan, c);
    co.r_value = core::restitution_energy_ratio(plan.wall, plan.restitutions[c.restitution_index].restitution);
    const std::vector<study::RunOutcome> runs = case_runs(plan, results, c, co.runs_with_error);
    if (!runs.empty()) co.statistics = study::case_statistics(runs, capacities.ntc2008_g, capacities.nzsee2016_g);
    o.runs_with_error += co.runs_with_error;
    o.cases.push_back(co);
  }
  o.flipped_runs = study::dt_check_flipped_runs(results);
  if (plan.dt_check) o.dt_check = study::dt_check_figures(plan, results);
  if (plan.analysis.evaluate_alarm) o.alarm = study::alarm_outcome(results);
  if (plan.analysis.arithmetic == sim::Arithmetic::fixed_point) o.fixed_vs_double = study::fixed_comparison(plan, results);
  if (plan.analysis.evaluate_alarm && plan.analysis.arithmetic == sim::Arithmetic::fixed_point) {
    o.published = study::published_alarm(results);
    o.published->work_budget_units = plan.analysis.work_budget_units;
    o.published->work_overflow = plan.analysis.work_overflow;
  }
  return o;
}

nlohmann::ordered_json summary_json(const study::StudyPlan& plan, const StudyRecords& records,
                                    const std::vector<study::RunResult>& results, const StudyOutcome& o) {
  nlohmann::ordered_json j;
  j["format"] = "rockwatch-study-summary";
  j["version"] = 1;
  nlohmann::ordered_json source;
  if (records.from_suite) {
    source["suite"] = records.suite_name;
    source["dir"] = records.suite_dir;
    source["sets"] = records.sets;
  } else {
    source["list"] = records.list_path;
  }
  j["records_source"] = source;
  j["plan"] = plan_json(plan);
  j["capacities"] = {{"ntc2008_g", o.capacities.ntc2008_g},
                     {"nzsee2016_g", o.capacities.nzsee2016_g},
                     {"lambda_ntc2008", 0.4},
                     {"lambda_nzsee2016", 0.6},
                     {"method", o.capacities.general_case
                                    ? "static non-linear kinematic check (SPEC section 5), K, X, T derived by virtual work"
                                    : "static non-linear kinematic check (SPEC section 5)"},
                     {"spectrum", kSpectrumProvenance}};
  j["runs"] = {{"total", results.size()}, {"with_error", o.runs_with_error}};
  nlohmann::ordered_json flipped = nlohmann::ordered_json::array();
  for (const std::size_t index : o.flipped_runs) {
    const study::RunKey key = study::run_key(plan, index);
    const study::StudyRecord& record = plan.records[key.record_index];
    flipped.push_back({{"run", index},
                       {"record", record.name},
                       {"component", record.component},
                       {"vertical", static_cast<bool>(plan.vertical[key.vertical_index])},
                       {"r", restitution_json(plan.restitutions[key.restitution_index])},
                       {"pga_g", plan.pga_g[key.pga_index]},
                       {"collapsed", study::double_collapsed(results[index])},
                       {"collapsed_reference", *results[index].collapsed_reference}});
  }
  const nlohmann::ordered_json flips =
      plan.dt_check ? nlohmann::ordered_json(o.flipped_runs.size()) : nlohmann::ordered_json(nullptr);
  j["dt_check"] = {{"enabled", plan.dt_check}, {"flips", flips}, {"flipped_runs", flipped}};
  if (o.dt_check) {
    const study::DtCheckFigures& d = *o.dt_check;
    const auto opt = [](const std::optional<double>& v) {
      return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
    };
    j["dt_check"]["reference"] = "double engine at reference_step_s";
    j["dt_check"]["max_step_s"] = plan.analysis.max_step_s;
    j["dt_check"]["reference_step_s"] = d.reference_step_s;
    j["dt_check"]["survivors_compared"] = d.survivors_compared;
    j["dt_check"]["max_abs_x_rel_error"] = {
        {"median", opt(d.rel_error_median)}, {"p90", opt(d.rel_error_p90)}, {"max", opt(d.rel_error_max)}};
    j["dt_check"]["max_abs_x_abs_error_m"] = {
        {"median", opt(d.abs_error_m_median)}, {"p90", opt(d.abs_error_m_p90)}, {"max", opt(d.abs_error_m_max)}};
  }
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  for (const CaseOutcome& c : o.cases) cases.push_back(case_json(plan, c));
  j["cases"] = cases;
  if (o.alarm) j["alarm"] = alarm_json(plan, *o.alarm);
  if (o.alarm && o.published) j["alarm"]["as_published"] = published_json(*o.published);
  if (o.fixed_vs_double) j["fixed_vs_double"] = fixed_json(plan, *o.fixed_vs_double);
  return j;
}

std::string study_summary_text(const StudyRequest& q, const study::StudyPlan& plan, const StudyRecords& records,
                               const StudyOutcome& o, const std::vector<std::string>& files,
                               const std::string& before_files) {
  std::string out = "rockwatch study: collapse probability of a two-block URM wall (SPEC 6, the design paper's "
                    "Table 3)\n\n";
  line(out, "records", records_text(records));
  if (records.from_suite) {
    line(out, "suite directory",
         records.suite_dir + (records.suite_found_by.empty() ? std::string(" (--suite)")
                                                             : " (the shipped suite " + std::string(kShippedSuiteName) +
                                                                   ", found in " + records.suite_found_by + ")"));
  }
  line(out, "wall", wall_text(q));
  line(out, "PGA levels", levels_text(plan));
  std::string r_text;
  for (const study::RestitutionCase& c : plan.restitutions) {
    r_text += (r_text.empty() ? "" : ", ") + c.label +
              format(" (r = %.4f)", core::restitution_energy_ratio(plan.wall, c.restitution));
  }
  line(out, "restitution", r_text);
  std::string v_text;
  for (const bool v : plan.vertical) v_text += (v_text.empty() ? "" : ", ") + std::string(v ? "with" : "without");
  line(out, "vertical", v_text);
  line(out, "analyses", format("%zu (model %s, kappa %s, max step %s s)", study::run_count(plan),
                               model_name(plan.analysis.model), number_text(plan.analysis.kappa).c_str(),
                               number_text(plan.analysis.max_step_s).c_str()));
  line(out, "static capacities",
       "NTC 2008 " + g_text(o.capacities.ntc2008_g) + ", NZSEE 2016 " + g_text(o.capacities.nzsee2016_g) +
           " (static check, npr9998-2015 spectrum: back-calculated)");
  if (o.runs_with_error > 0) {
    line(out, "refused runs", format("%zu analyses refused by the engine (e.g. lift-off G <= 0): no verdict, left out "
                                     "of the statistics; see the error column of runs.csv",
                                     o.runs_with_error));
  }
  for (const CaseOutcome& c : o.cases) case_text(out, o, c);
  out += "\n";
  if (plan.dt_check) {
    const study::DtCheckFigures& d = *o.dt_check;
    std::string text = format("against the double engine at %s s: %zu of %zu verdicts change",
                              number_text(d.reference_step_s).c_str(), o.flipped_runs.size(), study::run_count(plan));
    const std::size_t shown = o.flipped_runs.size() < 5 ? o.flipped_runs.size() : 5;
    for (std::size_t i = 0; i < shown; ++i) text += (i == 0 ? ": " : "; ") + run_text(plan, o.flipped_runs[i]);
    if (shown < o.flipped_runs.size()) text += "; ... (summary.json lists them all)";
    line(out, "dt check", text);
    if (d.rel_error_median) {
      line(out, "", format("survivors' max |x| (%zu) against it: median %.3g %%, p90 %.3g %%, max %.3g %% "
                           "(%.3g / %.3g / %.3g mm)",
                           d.survivors_compared, 100.0 * *d.rel_error_median, 100.0 * *d.rel_error_p90,
                           100.0 * *d.rel_error_max, 1e3 * *d.abs_error_m_median, 1e3 * *d.abs_error_m_p90,
                           1e3 * *d.abs_error_m_max));
    }
  }
  if (o.alarm) {
    const study::AlarmOutcome& a = *o.alarm;
    const core::AlarmSettings& st = plan.analysis.alarm;
    line(out, "alarm", format("lambda_w %s, hold %s s, energy margin %s (%s engine; verdicts of the double engine)",
                              number_text(st.lambda_warning).c_str(), number_text(st.hold_s).c_str(),
                              number_text(st.energy_margin).c_str(), arithmetic_name(plan.analysis.arithmetic)));
    for (const std::string& rule : options::opt_in_alarm_rule_texts(st)) line(out, "", rule);
    line(out, "", format("recall %s: %zu of %zu collapses flagged IMMINENT before t_collapse",
                         probability_text(a.recall).c_str(), a.collapsed_flagged, a.collapsed));
    line(out, "", format("false alarms %s: %zu of %zu survivors flagged IMMINENT",
                         probability_text(a.false_alarm_rate).c_str(), a.survivors_flagged, a.survivors));
    if (a.lead_time_s_median) {
      line(out, "", format("lead time median %.3f s, 5th percentile %.3f s, min %.3f s", *a.lead_time_s_median,
                           *a.lead_time_s_p05, *a.lead_time_s_min));
    }
    if (o.published) {
      const study::PublishedAlarm& p = *o.published;
      const double delay_s = p.imminent_delay_s_max ? *p.imminent_delay_s_max : 0.0;
      line(out, "", format("as the firmware's monitor publishes it (%d work units a call, %s at a full queue): "
                           "recall %s, false alarms %s, first IMMINENT late in %zu runs (at most %.3f s), samples "
                           "waited at most %u, %zu shed, %zu calls over the budget (the most work in a call %d units)",
                           static_cast<int>(p.work_budget_units), work_overflow_name(p.work_overflow),
                           probability_text(p.recall).c_str(), probability_text(p.false_alarm_rate).c_str(),
                           p.runs_imminent_delayed, delay_s, p.max_late_samples, p.shed_samples, p.overrun_calls,
                           static_cast<int>(p.max_call_units)));
    }
  }
  if (o.fixed_vs_double) {
    const study::FixedComparison& f = *o.fixed_vs_double;
    std::string text = format("%zu of %zu verdicts the same", f.verdicts_same, f.runs_compared);
    if (!f.verdict_flips.empty()) {
      text += format(", %zu flip%s", f.verdict_flips.size(), f.verdict_flips.size() == 1 ? "" : "s");
      if (plan.dt_check) text += format(" (%zu also flip at the reference step)", f.flips_also_at_reference.size());
    }
    if (f.max_abs_x_diff_m_max) {
      text += format("; survivors' max |x| within 0.5 mm on %zu of %zu (worst %.3g m)", f.survivors_within_half_mm,
                     f.survivors_compared, *f.max_abs_x_diff_m_max);
    }
    if (f.first_imminent_diff_samples_max) {
      text += format("; first IMMINENT within one step on %zu of %zu (worst %zu steps)", f.imminent_within_one_step,
                     f.imminent_compared, *f.first_imminent_diff_samples_max);
    }
    if (f.runs_saturated > 0) text += format("; %zu runs saturated", f.runs_saturated);
    line(out, "fixed vs double", text);
  }
  out += before_files;
  std::string file_list;
  for (const std::string& f : files) file_list += (file_list.empty() ? "" : ", ") + f;
  line(out, "files", file_list);
  return out;
}

}  // namespace rockwatch::cli
