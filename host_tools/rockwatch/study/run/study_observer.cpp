#include "study/run/study_observer.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"
#include "study/report/study_summary.hpp"
#include "study/plan/study_plan.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

nlohmann::ordered_json spread_json(const study::Spread& s) {
  return {{"median", number_or_null(s.median)}, {"p95", number_or_null(s.p95)}, {"max", number_or_null(s.max)},
          {"runs", s.n}};
}

nlohmann::ordered_json score_json(const study::ObserverScore& s) {
  nlohmann::ordered_json j;
  j["runs"] = s.runs;
  j["runs_with_error"] = s.runs_with_error;
  j["open_loop"] = alarm_score_json(s.open_loop);
  j["fused"] = alarm_score_json(s.fused);
  nlohmann::ordered_json x = {{"fused", spread_json(s.fused_x_rms_over_x_inst)},
                              {"open_loop", spread_json(s.open_x_rms_over_x_inst)}};
  x["fused"]["within_0_02"] = s.fused_x_within_2_percent;
  nlohmann::ordered_json r_after = spread_json(s.r_error_after_impacts);
  r_after["within_0_02"] = s.r_within_0_02;
  nlohmann::ordered_json x_inst_after = spread_json(s.x_inst_error_after_impacts);
  x_inst_after["within_0_03"] = s.x_inst_within_3_percent;
  nlohmann::ordered_json r_after_true = spread_json(s.r_error_after_true_impacts);
  r_after_true["within_0_02"] = s.r_within_0_02_after_true_impacts;
  nlohmann::ordered_json x_inst_after_true = spread_json(s.x_inst_error_after_true_impacts);
  x_inst_after_true["within_0_03"] = s.x_inst_within_3_percent_after_true_impacts;
  j["estimation"] = {{"x_rms_over_x_inst", x},
                     {"r_error_after_impacts", r_after},
                     {"r_error_final", spread_json(s.r_error_final)},
                     {"x_inst_relative_error_after_impacts", x_inst_after},
                     {"r_error_after_true_impacts", r_after_true},
                     {"x_inst_relative_error_after_true_impacts", x_inst_after_true}};
  j["runs_reinitialised"] = s.runs_reinitialised;
  j["runs_sensor_lost"] = s.runs_sensor_lost;
  return j;
}

nlohmann::ordered_json wall_json(const core::WallParameters& w) {
  return {{"b_m", w.b_m},     {"h1_m", w.h1_m}, {"h2_m", w.h2_m},         {"rho_kgpm3", w.rho_kgpm3},
          {"fp_npm", w.fp_npm}, {"a", w.a},     {"a_prime", w.a_prime},   {"g_mps2", w.g_mps2}};
}

nlohmann::ordered_json restitution_kind_json(const core::Restitution& r) {
  switch (r.kind) {
    case core::RestitutionKind::ana: return "ana";
    case core::RestitutionKind::exp: return "exp";
    case core::RestitutionKind::impulse: return "impulse";
    case core::RestitutionKind::value: return r.value;
  }
  return nullptr;
}

std::string csv_number(double v) { return number_text(v); }
std::string csv_optional(const std::optional<double>& v) { return v ? number_text(*v) : std::string(); }
const char* csv_bool(bool b) { return b ? "true" : "false"; }

// A CSV field: quoted when it holds a separator, a quote or a line break.
std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted_text = "\"";
  for (const char c : text) {
    if (c == '"') quoted_text += '"';
    quoted_text += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return quoted_text + "\"";
}

std::string opt3(const std::optional<double>& v) { return v ? format("%.3f", *v) : std::string("-"); }
std::string opt4(const std::optional<double>& v) { return v ? format("%.4f", *v) : std::string("-"); }

std::string alarm_line(const study::AlarmOutcome& a) {
  return format("recall %s (%zu/%zu), false alarms %s (%zu/%zu), lead median %s s, p05 %s s",
                probability_text(a.recall).c_str(), a.collapsed_flagged, a.collapsed,
                probability_text(a.false_alarm_rate).c_str(), a.survivors_flagged, a.survivors,
                opt3(a.lead_time_s_median).c_str(), opt3(a.lead_time_s_p05).c_str());
}

}  // namespace

study::ObserverEvaluationPlan observer_evaluation_plan(const study::StudyPlan& plan,
                                                       const core::ObserverOptions& observer) {
  study::ObserverEvaluationPlan e;
  e.nominal_restitution = core::Restitution{};  // r_exp
  e.cases = study::standard_mismatch_cases(plan.wall);
  e.observer = observer;
  return e;
}

nlohmann::ordered_json observer_plan_json(const study::ObserverEvaluationPlan& e) {
  nlohmann::ordered_json j;
  j["nominal_r"] = restitution_kind_json(e.nominal_restitution);
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  for (const study::MismatchCase& c : e.cases) {
    cases.push_back({{"name", c.name},
                     {"description", c.description},
                     {"wall", wall_json(c.wall)},
                     {"r", restitution_kind_json(c.restitution)},
                     {"r_value", core::restitution_energy_ratio(c.wall, c.restitution)},
                     {"accel_noise_mps2", c.accel_noise_mps2 ? nlohmann::ordered_json(*c.accel_noise_mps2)
                                                             : nlohmann::ordered_json(nullptr)}});
  }
  j["cases"] = cases;
  const sim::SensorModel& s = e.sensors;
  j["sensors"] = {{"x_noise_m", s.x_noise_m},
                  {"x_bias_m", s.x_bias_m},
                  {"x_quantum_m", s.x_quantum_m},
                  {"rate_hz", s.rate_hz > 0.0 ? nlohmann::ordered_json(s.rate_hz) : nlohmann::ordered_json("record")},
                  {"accelerometer", s.a_noise_mps2.has_value()},
                  {"seed", s.seed}};
  const core::ObserverOptions& o = e.observer;
  j["observer"] = {{"x_noise_m", o.x_noise_m},
                   {"a_noise_mps2", o.a_noise_mps2},
                   {"process_mps2", o.process_accel_mps2},
                   {"gate_chi2", o.gate_chi2}};
  // Only when changed: the description (what --resume compares) of a study written before the keys existed stays.
  const core::ObserverOptions defaults{};
  if (o.alarm_capacity_sigmas != defaults.alarm_capacity_sigmas) {
    j["observer"]["capacity_sigmas"] = o.alarm_capacity_sigmas;
  }
  if (o.accel_inform_peak_noises != defaults.accel_inform_peak_noises) {
    j["observer"]["accel_inform_peak_noises"] = o.accel_inform_peak_noises;
  }
  if (o.capacity_correlation != defaults.capacity_correlation) {
    j["observer"]["capacity_correlation"] = o.capacity_correlation;
  }
  j["r_after_impacts"] = e.r_after_impacts;
  return j;
}

nlohmann::ordered_json observer_summary_json(const study::ObserverEvaluationPlan& evaluation,
                                             const study::ObserverOutcome& outcome) {
  nlohmann::ordered_json j = score_json(outcome.all);
  nlohmann::ordered_json per_case = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < evaluation.cases.size(); ++i) {
    nlohmann::ordered_json c;
    c["name"] = evaluation.cases[i].name;
    c["description"] = evaluation.cases[i].description;
    const nlohmann::ordered_json scores = score_json(outcome.per_case[i]);
    for (const auto& item : scores.items()) c[item.key()] = item.value();
    per_case.push_back(c);
  }
  j["per_case"] = per_case;
  j["settings"] = observer_plan_json(evaluation);
  j["definitions"] = {
      {"verdict", "the TRUE wall's (double engine, collapsed or collapsed after the record), for both nominal runs"},
      {"open_loop", "the nominal wall (nominal r) on the ground motion alone, with the alarm"},
      {"fused", "the nominal wall with the wall observer fed the true wall's sensor samples, with the alarm"},
      {"recall", "true collapses flagged IMMINENT strictly before the true t_collapse / true collapses"},
      {"false_alarm_rate", "true survivors ever flagged IMMINENT / true survivors"},
      {"lead_time", "true t_collapse - first IMMINENT over the true collapses flagged before it"},
      {"x_rms_over_x_inst", "per run: RMS of x - x_true over the integration steps where either wall moves, divided "
                            "by the true wall's x_inst; median, 95th percentile and max over the runs with motion"},
      {"r_error_after_impacts", "per run with at least r_after_impacts impacts (|xd-| >= 1 mm/s) of the fused wall: "
                                "|r_hat - r_true| just before the next impact (or at the end)"},
      {"r_error_final", "the same runs: |r_hat - r_true| at the end of the analysis"},
      {"x_inst_relative_error_after_impacts", "the same runs: |x_inst_hat - x_inst_true| / x_inst_true when r_hat after "
                                              "r_after_impacts impacts was taken; within_0_03: runs within 3 %"},
      {"r_error_after_true_impacts", "per run whose TRUE wall has more than r_after_impacts counted impacts: |r_hat - "
                                     "r_true| before the input sample that holds the true wall's next counted impact"},
      {"x_inst_relative_error_after_true_impacts", "the same runs and time: |x_inst_hat - x_inst_true| / x_inst_true; "
                                                   "within_0_03: runs within 3 %"},
      {"percentile", "linear interpolation between order statistics (Hyndman-Fan type 7)"}};
  return j;
}

void write_observer_runs_csv(std::ostream& out, const study::StudyPlan& plan,
                             const study::ObserverEvaluationPlan& evaluation,
                             const std::vector<study::ObserverRunResult>& results) {
  out << "case,record,component,vertical,pga_g,true_collapsed,true_t_collapse_s,true_r,true_x_inst_m,true_max_abs_x_m,"
         "true_impacts,open_collapsed,open_t_first_imminent_s,fused_collapsed,fused_t_first_imminent_s,"
         "open_x_rms_error_m,fused_x_rms_error_m,r_estimate,r_estimate_after_impacts,fused_impacts,bias_estimate_m,"
         "n_updates,n_rejected,n_reinitialised,steps_sensor_lost,x_inst_estimate_m,x_inst_estimate_after_impacts_m,"
         "r_estimate_after_true_impacts,x_inst_estimate_after_true_impacts_m,run,error\n";
  for (std::size_t i = 0; i < results.size(); ++i) {
    const study::ObserverRunResult& r = results[i];
    if (!r.done) continue;
    const study::ObserverRunKey key = study::observer_run_key(plan, evaluation, i);
    const study::StudyRecord& rec = plan.records[key.record_index];
    std::string row = csv_text(evaluation.cases[key.case_index].name) + ',' + csv_text(rec.name) + ',' +
                      csv_text(rec.component) + ',' + (plan.vertical[key.vertical_index] ? "with" : "without") + ',' +
                      csv_number(plan.pga_g[key.pga_index]) + ',';
    if (r.error.empty()) {
      row += std::string(csv_bool(r.true_collapsed)) + ',' + csv_optional(r.true_t_collapse_s) + ',' +
             csv_number(r.true_r) + ',' + csv_number(r.true_x_inst_m) + ',' + csv_number(r.true_max_abs_x_m) + ',' +
             std::to_string(r.true_impacts) + ',' + csv_bool(r.open_collapsed) + ',' +
             csv_optional(r.open_t_first_imminent_s) + ',' + csv_bool(r.fused_collapsed) + ',' +
             csv_optional(r.fused_t_first_imminent_s) + ',' + csv_optional(r.open_x_rms_error_m) + ',' +
             csv_optional(r.fused_x_rms_error_m) + ',' + csv_number(r.r_estimate) + ',' +
             csv_optional(r.r_estimate_after_impacts) + ',' + std::to_string(r.fused_impacts) + ',' +
             csv_number(r.bias_estimate_m) + ',' + std::to_string(r.n_updates) + ',' + std::to_string(r.n_rejected) +
             ',' + std::to_string(r.n_reinitialised) + ',' + std::to_string(r.steps_sensor_lost) + ',' +
             csv_number(r.x_inst_estimate_m) + ',' + csv_optional(r.x_inst_estimate_after_impacts_m) + ',' +
             csv_optional(r.r_estimate_after_true_impacts) + ',' +
             csv_optional(r.x_inst_estimate_after_true_impacts_m) + ',' + std::to_string(i) + ",\n";
    } else {
      row += std::string(24, ',') + std::to_string(i) + ',' + csv_text(r.error) + '\n';
    }
    out << row;
  }
}

std::string observer_summary_text(const study::ObserverEvaluationPlan& evaluation, const study::ObserverOutcome& outcome) {
  std::string out;
  const study::ObserverScore& s = outcome.all;
  const sim::SensorModel& sensors = evaluation.sensors;
  out += format("\nWall observer evaluation: %zu runs (%zu mismatch cases), scored against the true wall's verdict\n",
                s.runs + s.runs_with_error, evaluation.cases.size());
  line(out, "sensors", format("displacement at the record's rate, noise %s m, zero offset %s m; nominal r_exp",
                              number_text(sensors.x_noise_m).c_str(), number_text(sensors.x_bias_m).c_str()));
  line(out, "open loop", alarm_line(s.open_loop));
  line(out, "fused", alarm_line(s.fused));
  line(out, "x RMS error / x_inst",
       format("fused median %s, p95 %s, max %s (%zu of %zu runs <= 0.02); open loop median %s, p95 %s",
              opt4(s.fused_x_rms_over_x_inst.median).c_str(), opt4(s.fused_x_rms_over_x_inst.p95).c_str(),
              opt4(s.fused_x_rms_over_x_inst.max).c_str(), s.fused_x_within_2_percent, s.fused_x_rms_over_x_inst.n,
              opt4(s.open_x_rms_over_x_inst.median).c_str(), opt4(s.open_x_rms_over_x_inst.p95).c_str()));
  line(out, "|r_hat - r|",
       format("after %d impacts median %s, p95 %s (%zu of %zu runs <= 0.02); at the end median %s, p95 %s",
              evaluation.r_after_impacts, opt4(s.r_error_after_impacts.median).c_str(),
              opt4(s.r_error_after_impacts.p95).c_str(), s.r_within_0_02, s.r_error_after_impacts.n,
              opt4(s.r_error_final.median).c_str(), opt4(s.r_error_final.p95).c_str()));
  line(out, "after true impacts",
       format("after %d counted impacts of the true wall: x_inst err median %s (%zu of %zu runs <= 0.03), |r err| "
              "median %s (%zu <= 0.02)",
              evaluation.r_after_impacts, opt4(s.x_inst_error_after_true_impacts.median).c_str(),
              s.x_inst_within_3_percent_after_true_impacts, s.x_inst_error_after_true_impacts.n,
              opt4(s.r_error_after_true_impacts.median).c_str(), s.r_within_0_02_after_true_impacts));
  if (s.runs_with_error > 0) line(out, "refused runs", format("%zu (no scores)", s.runs_with_error));
  for (std::size_t i = 0; i < evaluation.cases.size(); ++i) {
    const study::ObserverScore& c = outcome.per_case[i];
    line(out, evaluation.cases[i].name.c_str(),
         format("open loop recall %s FA %s; fused recall %s FA %s lead %s s; x err %s; |r err| %s; x_inst err %s "
                "(after the true wall's impacts %s)",
                probability_text(c.open_loop.recall).c_str(), probability_text(c.open_loop.false_alarm_rate).c_str(),
                probability_text(c.fused.recall).c_str(), probability_text(c.fused.false_alarm_rate).c_str(),
                opt3(c.fused.lead_time_s_median).c_str(), opt4(c.fused_x_rms_over_x_inst.median).c_str(),
                opt4(c.r_error_after_impacts.median).c_str(), opt4(c.x_inst_error_after_impacts.median).c_str(),
                opt4(c.x_inst_error_after_true_impacts.median).c_str()));
  }
  return out;
}

}  // namespace rockwatch::cli
