#include "simulate/simulate_forecast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rockwatch::cli {

namespace {

// The alarm's level at t (the last listed transition at or before t); none when transitions beyond the listed ones
// may have happened before t.
std::optional<core::AlarmLevel> alarm_level_at(const sim::AlarmSummary& a, double t_s) {
  core::AlarmLevel level = core::AlarmLevel::quiet;
  for (const sim::AlarmTransition& tr : a.transitions) {
    if (tr.t_s > t_s + 1e-9) return level;
    level = tr.level;
  }
  if (a.n_transitions > a.transitions.size()) return std::nullopt;
  return level;
}

}  // namespace

ForecastSeries run_forecasts(const SimulateRequest& q, const sim::GroundMotion& motion,
                             const sim::AnalysisResult& result) {
  ForecastSeries series;
  series.settings = *q.forecast;
  series.every_s = q.forecast_every_s;
  const std::vector<sim::HistoryRow>& h = result.history;
  if (h.empty()) return series;
  sim::EnsembleForecaster forecaster(q.wall, q.analysis.model, result.r, q.analysis.kappa, series.settings);
  // A forecast from the observer's fused state (its σ) takes that state's own shipped coefficients, any other the
  // open loop's (SPEC §10 "From the fused state"); a given calibration serves both.
  const std::optional<sim::ForecastCalibration> shipped =
      sim::default_forecast_calibration(series.settings.horizon_s, false);
  const std::optional<sim::ForecastCalibration> shipped_fused =
      sim::default_forecast_calibration(series.settings.horizon_s, true);
  series.calibration_applied = q.forecast_calibration.has_value() || (shipped && shipped_fused);
  if (q.forecast_calibration) {
    series.calibration = series.calibration_fused = *q.forecast_calibration;
  } else if (shipped && shipped_fused) {
    series.calibration = *shipped;
    series.calibration_fused = *shipped_fused;
  }
  // E/E_barrier of every history row (the study's feature, forecast_evaluation.cpp).
  std::vector<double> energy(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) energy[i] = forecaster.energy_ratio(h[i].x_m, h[i].xd_mps, h[i].side);
  // The ground as run: the record's ü to t_end, zero after it (the free motion), to the end of the history.
  const double dt = motion.dt_s;
  const double t_last = h.back().t_s;
  const auto n_ext = static_cast<std::size_t>(std::floor(t_last / dt + 1e-9)) + 1;
  std::vector<double> ug(std::max<std::size_t>(n_ext, 2), 0.0);
  for (std::size_t i = 0; i < ug.size() && i < motion.ug_mps2.size(); ++i) {
    if (double(i) * dt <= result.t_end_s + 1e-9) ug[i] = motion.ug_mps2[i];
  }
  const double t_stop = result.t_collapse_s ? *result.t_collapse_s : t_last;
  // With the observer: its estimates at the end of each sample, in time order (AnalysisResult::observer_history).
  const std::vector<sim::ObserverHistoryRow>& oh = result.observer_history;
  series.fused = !oh.empty();
  std::size_t orow = 0;
  std::size_t row = 0;
  for (long k = 0;; ++k) {
    const double t = std::round(double(k) * series.every_s * 1e9) / 1e9;  // 2.3, not 2.3000000000000003
    if (t > t_stop + 1e-9 || (result.t_collapse_s && t >= *result.t_collapse_s)) break;
    while (row + 1 < h.size() && h[row + 1].t_s <= t + 1e-9) ++row;
    const sim::HistoryRow& s = h[row];
    sim::ForecastState st;
    st.moving = !(s.x_m == 0.0 && s.xd_mps == 0.0);
    if (!st.moving) {
      ++series.at_rest;
      continue;
    }
    st.x_m = s.x_m;
    st.xd_mps = s.xd_mps;
    st.ug_now_mps2 = s.ug_mps2;
    // The fused state's spread and the estimated wall, as rockwatch-monitor --forecast passes them (ρ = 0: the
    // monitor's wall_estimate_t carries σ_x and σ_ẋ only; the two tools start from the same description of the wall).
    // Before the observer's first sample (the row of t = 0) the open loop's. The spread only while a displacement
    // reading bounds it (ObserverHistoryRow::x_active): with the sensor lost or never there, the filter's σ grows
    // with its process noise alone, and members drawn from it fall at once (SPEC §10 "From the fused state").
    while (orow + 1 < oh.size() && oh[orow + 1].t_s <= s.t_s + 1e-9) ++orow;
    std::optional<sim::ObserverHistoryRow> estimate;
    ForecastEntry e;
    if (!oh.empty() && oh[orow].t_s <= s.t_s + 1e-9) {
      estimate = oh[orow];
      e.fused = estimate->x_active;
      if (e.fused) {
        st.sigma_x_m = estimate->sigma_x_m;
        st.sigma_xd_mps = estimate->sigma_xd_mps;
      }
      st.sqrt_r = estimate->sqrt_r;
      st.capacity_scale = estimate->capacity_scale;
      st.stiffness_scale = estimate->stiffness_scale;
    }
    const std::size_t n = std::min(ug.size(), static_cast<std::size_t>(std::floor(s.t_s / dt + 1e-9)) + 1);
    e.t_s = t;
    e.observer = estimate;
    e.result = forecaster.forecast(st, ug.data(), std::max<std::size_t>(n, 2), dt);
    double e_max = energy[row];
    for (std::size_t i = row; i-- > 0 && h[i].t_s >= s.t_s - sim::kCalibrationEnergyWindow_s - 1e-9;) {
      e_max = std::max(e_max, energy[i]);
    }
    e.energy_ratio_max = e_max;
    e.x_over_x_inst = forecaster.x_over_x_inst(s.x_m, s.side);
    if (series.calibration_applied) {
      e.p_calibrated = sim::calibrated_probability(e.fused ? series.calibration_fused : series.calibration,
                                                   e.result.p_collapse, e.result.members,
                                                   e.energy_ratio_max, e.x_over_x_inst);
    }
    if (result.alarm.evaluated) e.alarm = alarm_level_at(result.alarm, t);
    series.entries.push_back(e);
  }
  return series;
}

nlohmann::ordered_json forecast_json(const ForecastSeries& s, bool with_alarm) {
  nlohmann::ordered_json j;
  j["members"] = s.settings.members;
  j["horizon_s"] = s.settings.horizon_s;
  j["every_s"] = s.every_s;
  j["step_s"] = s.settings.step_s;
  j["seed"] = s.settings.seed;
  j["at_rest_skipped"] = s.at_rest;
  if (s.calibration_applied) {
    const auto coefficients = [](const sim::ForecastCalibration& c) {
      return nlohmann::ordered_json{{"const", c.c[0]},
                                    {"logit_p", c.c[1]},
                                    {"energy_ratio_max_2s", c.c[2]},
                                    {"x_over_x_inst", c.c[3]},
                                    {"logit_p_x_energy_ratio_max_2s_capped", c.c[4]}};
    };
    // With the observer: the fused forecasts' set, and the other one for the entries whose "fused" is false.
    const sim::ForecastCalibration& main = s.fused ? s.calibration_fused : s.calibration;
    j["calibration"] = {{"coefficients", coefficients(main)},
                        {"horizon_s", main.horizon_s},
                        {"source", main.source},
                        {"applied", true}};
    if (s.fused) {
      j["calibration"]["not_fused"] = {{"coefficients", coefficients(s.calibration)},
                                       {"source", s.calibration.source}};
    }
  } else {
    j["calibration"] = {{"coefficients", nullptr},
                        {"horizon_s", nullptr},
                        {"source", std::string("none shipped for this horizon (") +
                                       sim::shipped_calibration_horizons() + "): give --forecast-calibration"},
                        {"applied", false}};
  }
  nlohmann::ordered_json series = nlohmann::ordered_json::array();
  for (const ForecastEntry& e : s.entries) {
    nlohmann::ordered_json x;
    x["t_s"] = e.t_s;
    x["p_collapse"] = e.result.p_collapse;
    x["p_collapse_se"] = e.result.p_collapse_se;
    x["q50_max_x_over_x_inst"] = e.result.q50_max_x_over_x_inst;
    x["q90_max_x_over_x_inst"] = e.result.q90_max_x_over_x_inst;
    x["p_collapse_calibrated"] = e.p_calibrated ? nlohmann::ordered_json(*e.p_calibrated) : nlohmann::ordered_json();
    x["energy_ratio_max_2s"] = e.energy_ratio_max;
    x["x_over_x_inst"] = e.x_over_x_inst;
    if (s.fused) {  // with --wall-sensors: what the members started from (null: before the observer's first sample)
      x["fused"] = e.fused;  // from the fused state with its σ (else σ = 0: no displacement reading within dropout_s)
      const sim::ObserverHistoryRow v = e.observer.value_or(sim::ObserverHistoryRow{});
      const auto put = [&](const char* key, double value) {
        x[key] = e.observer ? nlohmann::ordered_json(value) : nlohmann::ordered_json();
      };
      put("sigma_x_m", v.sigma_x_m);
      put("sigma_xd_mps", v.sigma_xd_mps);
      put("r_estimate", v.sqrt_r * v.sqrt_r);
      put("capacity_scale", v.capacity_scale);
      put("stiffness_scale", v.stiffness_scale);
    }
    if (with_alarm) {
      if (e.alarm) {
        x["alarm"] = core::alarm_level_name(*e.alarm);
      } else {
        x["alarm"] = nullptr;
      }
    }
    series.push_back(x);
  }
  j["series"] = series;
  return j;
}

std::string forecast_text(const ForecastSeries& s) {
  char buf[256];
  std::string out = "\nEnsemble forecast (SPEC section 10)\n";
  std::snprintf(buf, sizeof buf, "  %d members over %g s, one every %g s while the wall moves (seed %llu)\n",
                s.settings.members, s.settings.horizon_s, s.every_s,
                static_cast<unsigned long long>(s.settings.seed));
  out += buf;
  if (s.fused) {
    out += "  from the fused state, with the observer's sigma_x, sigma_xd, r and capacity (SPEC section 10)\n";
    std::size_t not_fused = 0;
    for (const ForecastEntry& e : s.entries) not_fused += e.fused ? 0 : 1;
    if (not_fused > 0) {
      std::snprintf(buf, sizeof buf,
                    "  %zu forecasts had no displacement reading within the dropout time: started from the state "
                    "without its sigma, with the open loop's calibration\n",
                    not_fused);
      out += buf;
    }
  }
  if (s.entries.empty()) {
    out += "  the wall was at rest at every forecast time: no forecast\n";
    return out;
  }
  const ForecastEntry* top = &s.entries.front();
  const ForecastEntry* first_half = nullptr;
  for (const ForecastEntry& e : s.entries) {
    if (e.result.p_collapse > top->result.p_collapse) top = &e;
    if (!first_half && e.result.p_collapse >= 0.5) first_half = &e;
  }
  std::snprintf(buf, sizeof buf, "  forecasts                  %zu (%zu times at rest skipped)\n", s.entries.size(),
                s.at_rest);
  out += buf;
  std::snprintf(buf, sizeof buf, "  highest P(collapse)        %.3f +- %.3f at t = %.3f s\n", top->result.p_collapse,
                top->result.p_collapse_se, top->t_s);
  out += buf;
  if (s.calibration_applied) {
    const ForecastEntry* top_c = &s.entries.front();
    for (const ForecastEntry& e : s.entries) {
      if (e.p_calibrated && (!top_c->p_calibrated || *e.p_calibrated > *top_c->p_calibrated)) top_c = &e;
    }
    if (top_c->p_calibrated) {
      std::snprintf(buf, sizeof buf, "  highest calibrated P       %.3f at t = %.3f s\n", *top_c->p_calibrated,
                    top_c->t_s);
      out += buf;
    }
  } else {
    std::snprintf(buf, sizeof buf, "  calibrated P               not given: coefficients are shipped for H = %s "
                  "(--forecast-calibration)\n", sim::shipped_calibration_horizons());
    out += buf;
  }
  if (first_half) {
    std::snprintf(buf, sizeof buf, "  first P(collapse) >= 0.5   t = %.3f s\n", first_half->t_s);
  } else {
    std::snprintf(buf, sizeof buf, "  first P(collapse) >= 0.5   never\n");
  }
  out += buf;
  return out;
}

}  // namespace rockwatch::cli
