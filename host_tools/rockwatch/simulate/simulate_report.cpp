#include "simulate/simulate_report.hpp"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <string>

#include "common/records_in/record_selection.hpp"
#include "common/process/text_report.hpp"
#include "common/process/verdict_json.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/observer_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

std::string restitution_text(const SimulateRequest& q, const sim::AnalysisResult& r) {
  const core::RestitutionKind kind = q.analysis.restitution.kind;
  std::string origin;
  switch (kind) {
    case core::RestitutionKind::ana: origin = "ana, paper eq. 17"; break;
    case core::RestitutionKind::exp: origin = "exp = 0.9 r_ana, paper eq. 18"; break;
    case core::RestitutionKind::impulse: origin = "impulse analysis with top restraint"; break;
    case core::RestitutionKind::value: origin = "given"; break;
  }
  return format("r = %.6f (%s); kinetic-energy ratio, velocity ratio sqrt(r) = %.6f", r.r, origin.c_str(),
                std::sqrt(r.r));
}

void describe_record(std::string& out, const char* label, const RecordInfo& info) {
  line(out, label, file_name(info.path) + " (" + format_name(info.format) + ", values in " + info.units + ")");
  if (!info.source.empty()) line(out, "", printable(info.source) + ", " + printable(info.path));
  // A suite record's header says what the source line says: once is enough.
  if (!info.description.empty() && info.description != info.source) line(out, "", printable(info.description));
  const double duration_s = info.dt_s * (static_cast<double>(info.samples) - 1.0);
  std::string span = format("%zu samples at dt %s s, duration %s s", info.samples, number_text(info.dt_s).c_str(),
                            number_text(duration_s).c_str());
  if (info.t0_s != 0.0) span += ", first sample at t = " + number_text(info.t0_s) + " s in the file";
  line(out, "", span);
}

// With an eccentric overburden (a != a') the two sides have their own threshold and x_inst; the engine's result
// holds the smaller, which alone would misstate the other side's collapse limit.
struct PerSide {
  double x_inst_m[2];        // index core::side_index: 0 = towards x < 0, 1 = towards x > 0
  double threshold_mps2[2];
  bool differ;
};

PerSide per_side(const SimulateRequest& q) {
  const core::ModelConstants<double> c = core::model_constants(q.wall, q.analysis.model);
  PerSide p{};
  for (const core::Side side : {core::Side::negative, core::Side::positive}) {
    const int i = core::side_index(side);
    p.x_inst_m[i] = core::x_inst_m(c, side, q.wall.g_mps2);
    p.threshold_mps2[i] = core::threshold_mps2(c, side, q.wall.g_mps2);
  }
  const auto close = [](double a, double b) { return std::fabs(a - b) <= 1e-12 * std::fmax(std::fabs(a), std::fabs(b)); };
  p.differ = !close(p.x_inst_m[0], p.x_inst_m[1]) || !close(p.threshold_mps2[0], p.threshold_mps2[1]);
  return p;
}

std::string verdict_line(const sim::AnalysisResult& r) {
  if (r.collapsed) return format("COLLAPSED at t = %.4f s", *r.t_collapse_s);
  if (r.collapse_after_end) {
    return format("COLLAPSED AFTER THE RECORD at t = %.4f s (free rocking after t_end = %.4f s)", *r.t_collapse_s,
                  r.t_end_s);
  }
  if (r.free_motion_undecided) {
    return format("UNDECIDED: still rocking %.0f s after the record without settling or collapsing",
                  r.t_final_s - r.t_end_s);
  }
  return "SURVIVED";
}

nlohmann::ordered_json alarm_json(const SimulateRequest& q, const sim::AlarmSummary& a) {
  nlohmann::ordered_json j;
  const core::AlarmSettings& s = q.analysis.alarm;
  j["settings"] = {{"lambda_warning", s.lambda_warning}, {"hold_s", s.hold_s}, {"energy_margin", s.energy_margin}};
  // The look-ahead rule (--imminent-horizon, SPEC §11): named when on (the default since 2026-12-01), absent at 0.
  if (s.imminent_horizon_s > 0.0) j["settings"]["imminent_horizon_s"] = s.imminent_horizon_s;
  if (s.energy_min_x > 0.0) j["settings"]["energy_min_x"] = s.energy_min_x;  // likewise (--energy-min-x)
  j["max_level"] = core::alarm_level_name(a.max_level);
  j["t_first_warning_s"] = number_or_null(a.t_first_warning_s);
  j["t_first_imminent_s"] = number_or_null(a.t_first_imminent_s);
  j["t_first_collapsed_s"] = number_or_null(a.t_first_collapsed_s);
  j["n_transitions"] = a.n_transitions;
  nlohmann::ordered_json transitions = nlohmann::ordered_json::array();
  for (const sim::AlarmTransition& t : a.transitions) {
    transitions.push_back({{"t_s", t.t_s},
                           {"level", core::alarm_level_name(t.level)},
                           {"previous", core::alarm_level_name(t.previous)},
                           {"reasons", alarm_reason_list(t.reasons)},
                           {"reason_bits", t.reasons},
                           {"x_m", t.x_m},
                           {"xd_mps", t.xd_mps},
                           {"t_to_instability_s", number_or_null(t.t_to_instability_s)},
                           {"energy_ratio", t.energy_ratio}});
  }
  j["transitions"] = transitions;
  if (a.published.measured) {
    const sim::AlarmSummary::Published& p = a.published;
    j["published"] = {{"work_budget_units", q.analysis.work_budget_units},
                      {"work_overflow", options::work_overflow_name(q.analysis.work_overflow)},
                      {"t_first_imminent_s", number_or_null(p.t_first_imminent_s)},
                      {"imminent_late_samples", p.imminent_late_calls},
                      {"t_first_collapsed_s", number_or_null(p.t_first_collapsed_s)},
                      {"late_samples", p.late_samples},
                      {"max_late_samples", p.max_late_calls},
                      {"shed_samples", p.shed_samples},
                      {"overruns", p.overruns},
                      {"max_call_units", p.max_call_units}};
  }
  return j;
}

void alarm_text(std::string& out, const SimulateRequest& q, const sim::AlarmSummary& a) {
  const core::AlarmSettings& s = q.analysis.alarm;
  out += "\nInstability alarm\n";
  line(out, "settings", format("WARNING at |x| >= %s x_inst; IMMINENT at |x| >= x_inst or E >= %s E_barrier moving "
                               "outward; hold %s s",
                               number_text(s.lambda_warning).c_str(), number_text(s.energy_margin).c_str(),
                               number_text(s.hold_s).c_str()));
  for (const std::string& rule : options::opt_in_alarm_rule_texts(s)) line(out, "", rule);
  line(out, "highest level", core::alarm_level_name(a.max_level));
  line(out, "first WARNING", time_text(a.t_first_warning_s, "never"));
  line(out, "first IMMINENT", time_text(a.t_first_imminent_s, "never"));
  line(out, "first COLLAPSED", time_text(a.t_first_collapsed_s, "never"));
  if (a.published.measured) {
    const sim::AlarmSummary::Published& p = a.published;
    line(out, "as published", format("by the firmware's engine (%d work units a call, %s at a full queue): first "
                                     "IMMINENT %s; %u samples late, the longest wait %u sample%s; %u shed; %u "
                                     "call%s over the budget, the most work in a call %d units",
                                     static_cast<int>(q.analysis.work_budget_units),
                                     options::work_overflow_name(q.analysis.work_overflow),
                                     time_text(p.t_first_imminent_s, "never").c_str(), p.late_samples,
                                     p.max_late_calls, p.max_late_calls == 1 ? "" : "s", p.shed_samples, p.overruns,
                                     p.overruns == 1 ? "" : "s", static_cast<int>(p.max_call_units)));
  }
  std::string count = std::to_string(a.n_transitions);
  if (a.transitions.size() < a.n_transitions) count += format(" (the first %zu listed)", a.transitions.size());
  line(out, "transitions", count);
  if (a.transitions.empty()) return;
  out += format("  %10s  %-9s  %11s  %11s  %7s  %s\n", "t [s]", "level", "x [m]", "t_inst [s]", "E/E_b", "reasons");
  for (const sim::AlarmTransition& t : a.transitions) {
    const std::string predicted = t.t_to_instability_s ? format("%.4f", *t.t_to_instability_s) : std::string("-");
    out += format("  %10.4f  %-9s  %11.7f  %11s  %7.3f  %s\n", t.t_s, core::alarm_level_name(t.level), t.x_m,
                  predicted.c_str(), t.energy_ratio, alarm_reason_names(t.reasons).c_str());
  }
  out += "  (t_inst: predicted time to reach |x| = x_inst with no further input, linear model; - when the wall would "
         "turn back)\n";
}

nlohmann::ordered_json observer_json(const SimulateRequest& q, const sim::ObserverSummary& s) {
  nlohmann::ordered_json j;
  j["r_estimate"] = s.r_estimate;
  j["sigma_r"] = s.sigma_r;
  j["r_estimate_after_impacts"] = number_or_null(s.r_estimate_after_impacts);
  j["r_after_impacts_count"] = q.analysis.observer_r_after_impacts;
  j["bias_estimate_m"] = s.bias_estimate_m;
  j["sigma_bias_m"] = s.sigma_bias_m;
  j["x_noise_m"] = s.x_noise_m;
  j["x_noise_readings"] = s.x_noise_readings;
  j["x_inst_estimate_m"] = s.x_inst_estimate_m;
  j["sigma_x_inst_m"] = s.sigma_x_inst_m;
  j["x_inst_estimate_after_impacts_m"] = number_or_null(s.x_inst_estimate_after_impacts_m);
  j["sigma_r_after_impacts"] = number_or_null(s.sigma_r_after_impacts);
  j["sigma_x_inst_after_impacts_m"] = number_or_null(s.sigma_x_inst_after_impacts_m);
  j["rocking_impacts"] = s.rocking_impacts;
  j["r_estimate_after_rocking_impacts"] = number_or_null(s.r_estimate_after_rocking_impacts);
  j["sigma_r_after_rocking_impacts"] = number_or_null(s.sigma_r_after_rocking_impacts);
  j["omega_estimate_rps"] = s.omega_estimate_rps;
  j["sigma_omega_rps"] = s.sigma_omega_rps;
  j["c_estimate_mps2"] = s.c_estimate_mps2;
  j["sigma_c_mps2"] = s.sigma_c_mps2;
  j["k_estimate_ps2"] = s.k_estimate_ps2;
  j["sigma_k_ps2"] = s.sigma_k_ps2;
  j["barrier_estimate_m2ps2"] = s.barrier_estimate_m2ps2;
  j["capacity_scale"] = s.capacity_scale;
  j["sigma_capacity_scale"] = s.sigma_capacity_scale;
  j["stiffness_scale"] = s.stiffness_scale;
  j["sigma_stiffness_scale"] = s.sigma_stiffness_scale;
  j["sigma_x_m"] = s.sigma_x_m;
  j["n_updates"] = s.n_updates;
  j["n_accel_updates"] = s.n_accel_updates;
  j["n_rejected"] = s.n_rejected;
  j["x_rms_innovation_m"] = s.x_rms_innovation_m;
  j["samples"] = s.samples_given;
  j["samples_used"] = s.samples_pushed;
  j["steps_sensor_lost"] = s.steps_sensor_lost;
  j["flags_seen"] = observer_flag_list(s.flags_seen);
  const core::ObserverCounters& c = s.counters;
  nlohmann::ordered_json counters = nlohmann::ordered_json::object();
  core::visit_observer_counters(c, [&counters](const char* name, std::int64_t value) { counters[name] = value; });
  j["counters"] = counters;
  const core::ObserverOptions& o = q.analysis.observer;
  j["settings"] = {{"x_noise_m", o.x_noise_m},
                   {"a_noise_mps2", o.a_noise_mps2},
                   {"process_mps2", o.process_accel_mps2},
                   {"gate_chi2", o.gate_chi2},
                   {"capacity_sigmas", o.alarm_capacity_sigmas},
                   {"accel_inform_peak_noises", o.accel_inform_peak_noises},
                   {"doubt_nis", o.doubt_nis},
                   {"quiet_motion_spread_noises", o.quiet_motion_spread_noises},
                   {"model_form_sigma", o.model_form_sigma},
                   {"doubt_model_form_sigma", o.doubt_model_form_sigma}};
  // Only when not 0 (the first is off by default, the second 0.25 since 2026-11-30, SPEC §11).
  if (o.capacity_min_x_fraction != 0.0) j["settings"]["capacity_min_x_fraction"] = o.capacity_min_x_fraction;
  if (o.doubt_capacity_min_x_fraction != 0.0) {
    j["settings"]["doubt_capacity_min_x_fraction"] = o.doubt_capacity_min_x_fraction;
  }
  if (o.capacity_correlation != 0.0) j["settings"]["capacity_correlation"] = o.capacity_correlation;  // opt-in
  return j;
}

void observer_text(std::string& out, const SimulateRequest& q, const sim::ObserverSummary& s, double nominal_r) {
  const core::ObserverOptions& o = q.analysis.observer;
  out += "\nWall observer (the result above is the fused state)\n";
  line(out, "sensor file", *q.wall_sensors_path);
  line(out, "settings", format("x noise %s m, a noise %s m/s2, process %s m/s2, gate chi2 %s",
                               number_text(o.x_noise_m).c_str(), number_text(o.a_noise_mps2).c_str(),
                               number_text(o.process_accel_mps2).c_str(), number_text(o.gate_chi2).c_str()));
  line(out, "samples", format("%zu in the file, %zu used up to the end of the analysis", s.samples_given,
                              s.samples_pushed));
  line(out, "updates", format("%lld displacement, %lld acceleration accepted; %lld rejected by the gate",
                              static_cast<long long>(s.n_updates), static_cast<long long>(s.n_accel_updates),
                              static_cast<long long>(s.n_rejected)));
  line(out, "restitution r", format("%.4f +- %.4f estimated (the model's nominal %.4f)", s.r_estimate, s.sigma_r, nominal_r));
  line(out, "", "after " + std::to_string(q.analysis.observer_r_after_impacts) + " impacts: " +
                    (s.r_estimate_after_impacts ? format("%.4f", *s.r_estimate_after_impacts)
                                                : std::string("fewer impacts")));
  line(out, "capacity x_inst", format("%.4f +- %.4f m estimated (omega %.3f +- %.3f rad/s, c %.3f +- %.3f m/s2, "
                                      "k %.3f +- %.3f 1/s2)", s.x_inst_estimate_m, s.sigma_x_inst_m,
                                      s.omega_estimate_rps, s.sigma_omega_rps, s.c_estimate_mps2, s.sigma_c_mps2,
                                      s.k_estimate_ps2, s.sigma_k_ps2));
  line(out, "transducer offset", format("%.6f +- %.6f m", s.bias_estimate_m, s.sigma_bias_m));
  line(out, "transducer noise", format("%.6f m used (%d readings at rest before the shaking)", s.x_noise_m,
                                       static_cast<int>(s.x_noise_readings)));
  line(out, "x innovation RMS", format("%.6f m", s.x_rms_innovation_m));
  if (s.steps_sensor_lost > 0) {
    line(out, "sensor lost", format("%zu steps ran on the model alone (%lld dropouts)", s.steps_sensor_lost,
                                    static_cast<long long>(s.counters.dropouts)));
  }
  line(out, "flags seen", observer_flag_names(s.flags_seen));
}

}  // namespace

const char* verdict_word(const sim::AnalysisResult& r) {
  if (r.collapsed) return "COLLAPSED";
  if (r.collapse_after_end) return "COLLAPSED AFTER THE RECORD";
  if (r.free_motion_undecided) return "UNDECIDED";
  return "SURVIVED";
}

nlohmann::ordered_json result_json(const SimulateRequest& q, const sim::AnalysisResult& r) {
  nlohmann::ordered_json j;
  add_verdict_json(j, r);
  j["t_first_motion_s"] = number_or_null(r.t_first_motion_s);
  j["x_inst_m"] = r.x_inst_m;
  j["threshold_mps2"] = r.threshold_mps2;
  j["r"] = r.r;
  j["pga_mps2"] = r.pga_mps2;
  j["dt_s"] = r.dt_s;
  j["duration_s"] = r.duration_s;
  j["model"] = model_name(q.analysis.model);
  j["kappa"] = q.analysis.kappa;
  if (q.analysis.initial_x_m) j["x0_m"] = *q.analysis.initial_x_m;
  if (q.wall_file_path) j["wall_file"] = *q.wall_file_path;
  if (q.arith_given) {
    j["arithmetic"] = arithmetic_name(r.arithmetic);
    if (r.arithmetic == sim::Arithmetic::fixed_point) j["saturated"] = r.saturated;
  }
  if (q.analysis.evaluate_alarm) j["alarm"] = alarm_json(q, r.alarm);
  if (q.wall_sensors_path) j["observer"] = observer_json(q, r.observer);
  add_selection_json(j, q.record);
  return j;
}

std::string summary_text(const SimulateRequest& q, const InputMotion& in, const sim::AnalysisResult& r) {
  const core::WallParameters& w = q.wall;
  const double g = w.g_mps2;
  std::string out;
  out += "rockwatch simulate: out-of-plane rocking of a two-block URM wall (SPEC 1-4), per metre of wall\n\n";

  out += "Input\n";
  describe_record(out, "horizontal record", in.horizontal);
  if (in.vertical_from_third_column) {
    line(out, "vertical record", "third column of " + file_name(in.horizontal.path));
  } else if (in.vertical) {
    describe_record(out, "vertical record", *in.vertical);
  } else {
    line(out, "vertical record", "none (v'' = 0)");
  }
  if (q.scale_pga_g) {
    line(out, "scaling", format("factor %.6g: PGA %.4f g -> %.4f g%s", in.scale_factor, in.horizontal.peak_as_read_mps2 / g,
                                *q.scale_pga_g, in.motion.vg_mps2.empty() ? "" : ", vertical by the same factor"));
  }
  line(out, "PGA as run", format("%.4f g = %.4f m/s2", r.pga_mps2 / g, r.pga_mps2));
  if (!in.motion.vg_mps2.empty()) {
    const double pv = sim::peak_abs(in.motion.vg_mps2);
    line(out, "vertical peak as run", format("%.4f g = %.4f m/s2", pv / g, pv));
  }

  out += "\nWall (per metre of wall)\n";
  std::string base = q.wall_file_path ? "wall file " + *q.wall_file_path : q.wall_name + " wall (design paper, Table 2)";
  if (!q.wall_options_given.empty()) {
    base += " with ";
    for (std::size_t i = 0; i < q.wall_options_given.size(); ++i) base += (i == 0 ? "" : ", ") + q.wall_options_given[i];
    base += " given";
  }
  line(out, "base wall", base);
  line(out, "geometry", format("b %s m, h1 %s m, h2 %s m (h = %s m, h/b = %.4g)", number_text(w.b_m).c_str(),
                               number_text(w.h1_m).c_str(), number_text(w.h2_m).c_str(),
                               number_text(w.h1_m + w.h2_m).c_str(), (w.h1_m + w.h2_m) / w.b_m));
  line(out, "masonry", format("rho %s kg/m3, weight %.6g N per m of wall", number_text(w.rho_kgpm3).c_str(),
                              w.rho_kgpm3 * w.b_m * (w.h1_m + w.h2_m) * g));
  line(out, "overburden", format("Fp %s N per m of wall at a = %s (x < 0), a' = %s (x > 0)", number_text(w.fp_npm).c_str(),
                                 number_text(w.a).c_str(), number_text(w.a_prime).c_str()));
  line(out, "gravity", number_text(g) + " m/s2");
  const PerSide sides = per_side(q);
  if (sides.differ) {
    line(out, "rocking threshold", format("%.6f m/s2 = %.6f g towards x > 0 (u'' < -thr), %.6f m/s2 = %.6f g towards "
                                          "x < 0 (u'' > thr); v'' = 0",
                                          sides.threshold_mps2[1], sides.threshold_mps2[1] / g, sides.threshold_mps2[0],
                                          sides.threshold_mps2[0] / g));
    line(out, "", format("PGA / smaller threshold = %.3f", r.pga_mps2 / r.threshold_mps2));
    line(out, "x_inst", format("%.7f m towards x > 0, %.7f m towards x < 0", sides.x_inst_m[1], sides.x_inst_m[0]));
  } else {
    line(out, "rocking threshold", format("%.6f m/s2 = %.6f g (v'' = 0); PGA / threshold = %.3f", r.threshold_mps2,
                                          r.threshold_mps2 / g, r.pga_mps2 / r.threshold_mps2));
    line(out, "x_inst", format("%.7f m (theta1 = x/h1 = %.5f rad)", r.x_inst_m, r.x_inst_m / w.h1_m));
  }

  out += "\nAnalysis\n";
  line(out, "model", std::string(model_name(q.analysis.model)) +
                         (q.analysis.model == core::ModelKind::linear ? " (the paper's)" : " (all terms of SPEC 1)"));
  line(out, "arithmetic", r.arithmetic == sim::Arithmetic::fixed_point
                              ? "fixed point (the monitor's engine)"
                              : "double precision (the verified engine)");
  line(out, "restitution", restitution_text(q, r));
  const double kappa = q.analysis.kappa;
  if (sides.differ) {
    line(out, "collapse criterion", format("|x| >= kappa x_inst = %.7f m towards x > 0, %.7f m towards x < 0 (kappa %s)",
                                           kappa * sides.x_inst_m[1], kappa * sides.x_inst_m[0],
                                           number_text(kappa).c_str()));
  } else {
    line(out, "collapse criterion", format("|x| >= kappa x_inst = %s x %.7f = %.7f m", number_text(kappa).c_str(),
                                           r.x_inst_m, kappa * r.x_inst_m));
  }
  const double sub_steps = std::round(in.motion.dt_s / r.dt_s);
  line(out, "integration", format("Newmark beta 1/4, gamma 1/2, dt %s s (%.0f per record step), impacts located in the step",
                                  number_text(r.dt_s).c_str(), sub_steps));
  std::string span = format("record 0 to %.4f s; forced phase to t_end = %.4f s", r.duration_s, r.t_end_s);
  if (r.collapsed) {
    span += format("; stopped at the collapse, t = %.4f s", *r.t_collapse_s);
  } else if (r.t_final_s > r.t_end_s) {
    span += format("; then free rocking (no input) to %.4f s", r.t_final_s);
  }
  line(out, "time span", span);

  out += "\nResult\n";
  line(out, "VERDICT", verdict_line(r));
  if (r.max_abs_x_m > 0.0) {
    const std::string ratio = sides.differ ? std::string() : format("%.3f x_inst, ", r.max_abs_x_m / r.x_inst_m);
    line(out, "max |x|", format("%.7f m at t = %.4f s (%stheta1 = %.5f rad)", r.max_abs_x_m, r.t_max_abs_x_s,
                                ratio.c_str(), r.max_abs_x_m / w.h1_m));
  } else {
    line(out, "max |x|", "0 m: the wall did not rock");
  }
  line(out, "t_exceed (|x| >= x_inst)", time_text(r.t_exceed_s, "never"));
  line(out, "first motion", time_text(r.t_first_motion_s, "never: the input stayed below the rocking threshold"));
  line(out, "impacts", format("%d with |xd-| >= 1 mm/s (%d in all)", r.n_impacts, r.n_impacts_total));
  if (r.saturated) {
    line(out, "SATURATED", "a fixed-point quantity reached its range limit: the result is unreliable");
  }
  if (q.wall_sensors_path) observer_text(out, q, r.observer, r.r);
  if (q.analysis.evaluate_alarm) alarm_text(out, q, r.alarm);
  return out;
}

}  // namespace rockwatch::cli
